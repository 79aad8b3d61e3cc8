// Minimal dependency-free SVG line/scatter plot, so every run can leave a picture of its result.
#include "analysis/svg_plot.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <stdexcept>

namespace mesodpd {

namespace {

// Axis range widened to whole multiples of a 1-2-5 step, so ticks land on round numbers.
struct Axis {
  double lo;
  double hi;
  double step;
  std::vector<double> ticks;
};

Axis nice_axis(double lo, double hi, int target_ticks) {
  if (!(lo <= hi)) {  // no finite data at all
    lo = 0.0;
    hi = 1.0;
  }
  const double scale = std::max({1.0, std::fabs(lo), std::fabs(hi)});
  if (hi - lo <= 1e-12 * scale) {  // a single value still needs a visible range
    const double pad = lo != 0.0 ? 0.1 * std::fabs(lo) : 1.0;
    lo -= pad;
    hi += pad;
  }
  const double raw = (hi - lo) / target_ticks;
  const double mag = std::pow(10.0, std::floor(std::log10(raw)));
  const double f = raw / mag;
  const double step = (f <= 1.0 ? 1.0 : f <= 2.0 ? 2.0 : f <= 5.0 ? 5.0 : 10.0) * mag;
  // Tolerances keep a value that is already on a tick from spilling into one more step.
  const double klo = std::floor(lo / step + 1e-9);
  const double khi = std::ceil(hi / step - 1e-9);
  Axis a{klo * step, khi * step, step, {}};
  const auto count = static_cast<long>(khi - klo);
  for (long k = 0; k <= count; ++k) a.ticks.push_back((klo + static_cast<double>(k)) * step);  // no drift
  return a;
}

std::string tick_label(double v, double step) {
  if (std::fabs(v) < 1e-9 * step) v = 0.0;  // avoid "-0" and 1e-17 from k*step
  const double big = std::max(std::fabs(v), step);
  if (big >= 1e5 || step < 1e-4) return fmt::format("{:.3g}", v);
  const int decimals = std::max(0, -static_cast<int>(std::floor(std::log10(step) + 1e-9)));
  return fmt::format("{:.{}f}", v, decimals);
}

std::string escape(const std::string& s) {
  std::string out;
  out.reserve(s.size());
  for (char c : s) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      case '\'':
        out += "&apos;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

const char* palette_color(std::size_t k) {
  static const char* const kPalette[] = {"#1f77b4", "#d62728", "#2ca02c", "#ff7f0e", "#9467bd", "#8c564b"};
  return kPalette[k % (sizeof(kPalette) / sizeof(kPalette[0]))];
}

bool has_bar(const SvgSeries& s, std::size_t i) {
  return !s.yerr.empty() && std::isfinite(s.yerr[i]) && s.yerr[i] > 0.0;
}

}  // namespace

void write_svg_plot(const std::string& path, const std::string& title, const std::string& xlabel,
                    const std::string& ylabel, const std::vector<SvgSeries>& series,
                    const std::vector<std::string>& notes) {
  double xmin = std::numeric_limits<double>::infinity(), xmax = -xmin;
  double ymin = xmin, ymax = -xmin;
  for (const SvgSeries& s : series) {
    if (s.x.size() != s.y.size() || (!s.yerr.empty() && s.yerr.size() != s.y.size())) {
      throw std::invalid_argument(fmt::format("write_svg_plot: series '{}' has mismatched lengths", s.label));
    }
    for (std::size_t i = 0; i < s.x.size(); ++i) {
      if (!std::isfinite(s.x[i]) || !std::isfinite(s.y[i])) continue;
      const double e = has_bar(s, i) ? s.yerr[i] : 0.0;
      xmin = std::min(xmin, s.x[i]);
      xmax = std::max(xmax, s.x[i]);
      ymin = std::min(ymin, s.y[i] - e);
      ymax = std::max(ymax, s.y[i] + e);
    }
  }
  const Axis ax = nice_axis(xmin, xmax, 6);
  const Axis ay = nice_axis(ymin, ymax, 6);

  const double width = 720.0;
  const double height = 480.0 + 18.0 * static_cast<double>(notes.size());
  const double left = 85.0, right = width - 20.0, top = 45.0;
  const double bottom = height - 65.0 - 18.0 * static_cast<double>(notes.size());
  const auto px = [&](double x) { return left + (x - ax.lo) / (ax.hi - ax.lo) * (right - left); };
  const auto py = [&](double y) { return bottom - (y - ay.lo) / (ay.hi - ay.lo) * (bottom - top); };

  std::string svg;
  svg += fmt::format(
      "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{0}\" height=\"{1}\" viewBox=\"0 0 {0} {1}\" "
      "font-family=\"sans-serif\" font-size=\"13\">\n",
      width, height);
  svg += "<rect x=\"0\" y=\"0\" width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
  svg += fmt::format("<text x=\"{:.1f}\" y=\"28\" text-anchor=\"middle\" font-size=\"16\">{}</text>\n",
                     width / 2, escape(title));

  // Grid and ticks.
  for (double t : ax.ticks) {
    const double x = px(t);
    svg += fmt::format(
        "<line x1=\"{0:.2f}\" y1=\"{1:.2f}\" x2=\"{0:.2f}\" y2=\"{2:.2f}\" stroke=\"#e0e0e0\"/>\n", x, top,
        bottom);
    svg +=
        fmt::format("<line x1=\"{0:.2f}\" y1=\"{1:.2f}\" x2=\"{0:.2f}\" y2=\"{2:.2f}\" stroke=\"black\"/>\n",
                    x, bottom, bottom + 5);
    svg += fmt::format("<text x=\"{:.2f}\" y=\"{:.2f}\" text-anchor=\"middle\">{}</text>\n", x, bottom + 20,
                       tick_label(t, ax.step));
  }
  for (double t : ay.ticks) {
    const double y = py(t);
    svg += fmt::format(
        "<line x1=\"{1:.2f}\" y1=\"{0:.2f}\" x2=\"{2:.2f}\" y2=\"{0:.2f}\" stroke=\"#e0e0e0\"/>\n", y, left,
        right);
    svg +=
        fmt::format("<line x1=\"{1:.2f}\" y1=\"{0:.2f}\" x2=\"{2:.2f}\" y2=\"{0:.2f}\" stroke=\"black\"/>\n",
                    y, left - 5, left);
    svg += fmt::format("<text x=\"{:.2f}\" y=\"{:.2f}\" text-anchor=\"end\">{}</text>\n", left - 8, y + 4,
                       tick_label(t, ay.step));
  }
  svg += fmt::format(
      "<rect x=\"{:.2f}\" y=\"{:.2f}\" width=\"{:.2f}\" height=\"{:.2f}\" fill=\"none\" stroke=\"black\"/>\n",
      left, top, right - left, bottom - top);
  svg += fmt::format("<text x=\"{:.2f}\" y=\"{:.2f}\" text-anchor=\"middle\">{}</text>\n", (left + right) / 2,
                     bottom + 42, escape(xlabel));
  svg +=
      fmt::format("<text transform=\"translate(20 {:.2f}) rotate(-90)\" text-anchor=\"middle\">{}</text>\n",
                  (top + bottom) / 2, escape(ylabel));

  // Data: error bars under the line, markers on top.
  for (std::size_t k = 0; k < series.size(); ++k) {
    const SvgSeries& s = series[k];
    const std::string color = escape(s.color.empty() ? palette_color(k) : s.color);
    svg += fmt::format("<g stroke=\"{0}\" fill=\"{0}\">\n", color);
    for (std::size_t i = 0; i < s.x.size(); ++i) {
      if (!std::isfinite(s.x[i]) || !std::isfinite(s.y[i]) || !has_bar(s, i)) continue;
      const double x = px(s.x[i]), y1 = py(s.y[i] - s.yerr[i]), y2 = py(s.y[i] + s.yerr[i]);
      svg += fmt::format("<line x1=\"{0:.2f}\" y1=\"{1:.2f}\" x2=\"{0:.2f}\" y2=\"{2:.2f}\"/>\n", x, y1, y2);
      svg += fmt::format("<line x1=\"{0:.2f}\" y1=\"{2:.2f}\" x2=\"{1:.2f}\" y2=\"{2:.2f}\"/>\n", x - 3,
                         x + 3, y1);
      svg += fmt::format("<line x1=\"{0:.2f}\" y1=\"{2:.2f}\" x2=\"{1:.2f}\" y2=\"{2:.2f}\"/>\n", x - 3,
                         x + 3, y2);
    }
    if (s.line) {
      // A non-finite point breaks the line rather than joining across the gap.
      std::string pts;
      const auto flush = [&] {
        if (!pts.empty())
          svg += fmt::format("<polyline fill=\"none\" stroke-width=\"1.5\" points=\"{}\"/>\n", pts);
        pts.clear();
      };
      for (std::size_t i = 0; i < s.x.size(); ++i) {
        if (!std::isfinite(s.x[i]) || !std::isfinite(s.y[i])) {
          flush();
          continue;
        }
        pts += fmt::format("{}{:.2f},{:.2f}", pts.empty() ? "" : " ", px(s.x[i]), py(s.y[i]));
      }
      flush();
    }
    if (s.markers) {
      for (std::size_t i = 0; i < s.x.size(); ++i) {
        if (!std::isfinite(s.x[i]) || !std::isfinite(s.y[i])) continue;
        svg += fmt::format("<circle cx=\"{:.2f}\" cy=\"{:.2f}\" r=\"3\"/>\n", px(s.x[i]), py(s.y[i]));
      }
    }
    svg += "</g>\n";
  }

  // Legend in the top-right corner of the axis box.
  std::vector<std::size_t> shown;
  std::size_t longest = 0;
  for (std::size_t k = 0; k < series.size(); ++k) {
    if (series[k].label.empty()) continue;
    shown.push_back(k);
    longest = std::max(longest, series[k].label.size());
  }
  if (!shown.empty()) {
    const double lw = 40.0 + 7.5 * static_cast<double>(longest);
    const double lh = 8.0 + 18.0 * static_cast<double>(shown.size());
    const double lx = right - lw - 8.0, ly = top + 8.0;
    svg += fmt::format(
        "<rect x=\"{:.2f}\" y=\"{:.2f}\" width=\"{:.2f}\" height=\"{:.2f}\" fill=\"white\" "
        "fill-opacity=\"0.85\" "
        "stroke=\"#888888\"/>\n",
        lx, ly, lw, lh);
    for (std::size_t row = 0; row < shown.size(); ++row) {
      const SvgSeries& s = series[shown[row]];
      const std::string color = escape(s.color.empty() ? palette_color(shown[row]) : s.color);
      const double y = ly + 15.0 + 18.0 * static_cast<double>(row);
      if (s.line || !s.markers) {
        svg += fmt::format(
            "<line x1=\"{:.2f}\" y1=\"{:.2f}\" x2=\"{:.2f}\" y2=\"{:.2f}\" stroke=\"{}\" "
            "stroke-width=\"1.5\"/>\n",
            lx + 6, y - 4, lx + 28, y - 4, color);
      }
      if (s.markers) {
        svg +=
            fmt::format("<circle cx=\"{:.2f}\" cy=\"{:.2f}\" r=\"3\" fill=\"{}\"/>\n", lx + 17, y - 4, color);
      }
      svg += fmt::format("<text x=\"{:.2f}\" y=\"{:.2f}\">{}</text>\n", lx + 34, y, escape(s.label));
    }
  }

  for (std::size_t i = 0; i < notes.size(); ++i) {
    svg += fmt::format("<text x=\"{:.2f}\" y=\"{:.2f}\">{}</text>\n", left,
                       bottom + 64 + 18.0 * static_cast<double>(i), escape(notes[i]));
  }
  svg += "</svg>\n";

  std::ofstream os(path);
  if (!os) throw std::runtime_error(fmt::format("write_svg_plot: cannot open '{}' for writing", path));
  os << svg;
  if (!os) throw std::runtime_error(fmt::format("write_svg_plot: write to '{}' failed", path));
}

}  // namespace mesodpd
