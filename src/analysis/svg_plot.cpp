// Minimal dependency-free SVG line/scatter plot, so every run can leave a picture of its result.
#include "analysis/svg_plot.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "io/atomic_file.hpp"

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

  write_file_atomically(path, [&](std::ostream& os) { os << svg; });
}

namespace {
// Perceptually ordered colours (viridis at nine stops), interpolated linearly in RGB.
std::string colour_of(double t) {
  static constexpr unsigned char kStops[9][3] = {{68, 1, 84},    {71, 44, 122},  {59, 81, 139},
                                                  {44, 113, 142}, {33, 144, 141}, {39, 173, 129},
                                                  {92, 200, 99},  {170, 220, 50}, {253, 231, 37}};
  t = std::clamp(t, 0.0, 1.0) * 8.0;
  const int k = std::min(7, static_cast<int>(t));
  const double f = t - k;
  unsigned char rgb[3];
  for (int c = 0; c < 3; ++c) rgb[c] = static_cast<unsigned char>(std::lround(kStops[k][c] + f * (kStops[k + 1][c] - kStops[k][c])));
  return fmt::format("#{:02x}{:02x}{:02x}", rgb[0], rgb[1], rgb[2]);
}
}  // namespace

void write_svg_map(const std::string& path, const std::string& title, const std::string& xlabel,
                   const std::string& ylabel, const SvgGrid& grid, const std::string& value_label,
                   const std::vector<std::string>& notes) {
  if (grid.nx < 1 || grid.ny < 1 || grid.values.size() != grid.nx * grid.ny || !(grid.x1 > grid.x0) ||
      !(grid.y1 > grid.y0))
    throw std::invalid_argument("write_svg_map: values must hold nx x ny entries over a non-empty rectangle");
  double vmin = std::numeric_limits<double>::infinity(), vmax = -vmin;
  for (double v : grid.values)
    if (std::isfinite(v)) vmin = std::min(vmin, v), vmax = std::max(vmax, v);
  const Axis scale = nice_axis(vmin, vmax, 5);
  // The map keeps the aspect ratio of the region, within limits that keep it legible.
  const double map_w = 560.0;
  const double map_h = std::clamp(map_w * (grid.y1 - grid.y0) / (grid.x1 - grid.x0), 120.0, 900.0);
  const double left = 85.0, top = 45.0, right = left + map_w, bottom = top + map_h;
  const double width = right + 130.0;
  const double height = bottom + 65.0 + 18.0 * static_cast<double>(notes.size());
  const Axis ax = nice_axis(grid.x0, grid.x1, 6), ay = nice_axis(grid.y0, grid.y1, 6);
  const auto px = [&](double x) { return left + (x - grid.x0) / (grid.x1 - grid.x0) * map_w; };
  const auto py = [&](double y) { return bottom - (y - grid.y0) / (grid.y1 - grid.y0) * map_h; };
  std::string svg = fmt::format(
      "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{0}\" height=\"{1}\" viewBox=\"0 0 {0} {1}\" "
      "font-family=\"sans-serif\" font-size=\"13\">\n<rect x=\"0\" y=\"0\" width=\"100%\" height=\"100%\" fill=\"white\"/>\n",
      width, height);
  svg += fmt::format("<text x=\"{:.1f}\" y=\"28\" text-anchor=\"middle\" font-size=\"16\">{}</text>\n", width / 2,
                     escape(title));
  // Cells (grey where there is no value), slightly oversized so that no hairline gaps show.
  const double cw = map_w / static_cast<double>(grid.nx), ch = map_h / static_cast<double>(grid.ny);
  svg += "<g shape-rendering=\"crispEdges\">\n";
  for (std::size_t j = 0; j < grid.ny; ++j)
    for (std::size_t i = 0; i < grid.nx; ++i) {
      const double v = grid.values[j * grid.nx + i];
      const std::string fill = std::isfinite(v) ? colour_of((v - scale.lo) / (scale.hi - scale.lo)) : "#d0d0d0";
      svg += fmt::format("<rect x=\"{:.2f}\" y=\"{:.2f}\" width=\"{:.2f}\" height=\"{:.2f}\" fill=\"{}\"/>\n",
                         left + cw * static_cast<double>(i), bottom - ch * static_cast<double>(j + 1), cw + 0.3, ch + 0.3,
                         fill);
    }
  svg += "</g>\n";
  svg += fmt::format("<rect x=\"{:.2f}\" y=\"{:.2f}\" width=\"{:.2f}\" height=\"{:.2f}\" fill=\"none\" stroke=\"black\"/>\n",
                     left, top, map_w, map_h);
  for (double t : ax.ticks) {
    if (t < grid.x0 - 1e-9 * ax.step || t > grid.x1 + 1e-9 * ax.step) continue;
    svg += fmt::format("<line x1=\"{0:.2f}\" y1=\"{1:.2f}\" x2=\"{0:.2f}\" y2=\"{2:.2f}\" stroke=\"black\"/>\n", px(t), bottom,
                       bottom + 5);
    svg += fmt::format("<text x=\"{:.2f}\" y=\"{:.2f}\" text-anchor=\"middle\">{}</text>\n", px(t), bottom + 20,
                       tick_label(t, ax.step));
  }
  for (double t : ay.ticks) {
    if (t < grid.y0 - 1e-9 * ay.step || t > grid.y1 + 1e-9 * ay.step) continue;
    svg += fmt::format("<line x1=\"{1:.2f}\" y1=\"{0:.2f}\" x2=\"{2:.2f}\" y2=\"{0:.2f}\" stroke=\"black\"/>\n", py(t), left - 5,
                       left);
    svg += fmt::format("<text x=\"{:.2f}\" y=\"{:.2f}\" text-anchor=\"end\">{}</text>\n", left - 8, py(t) + 4,
                       tick_label(t, ay.step));
  }
  svg += fmt::format("<text x=\"{:.2f}\" y=\"{:.2f}\" text-anchor=\"middle\">{}</text>\n", (left + right) / 2, bottom + 42,
                     escape(xlabel));
  svg += fmt::format("<text transform=\"translate(20 {:.2f}) rotate(-90)\" text-anchor=\"middle\">{}</text>\n",
                     (top + bottom) / 2, escape(ylabel));
  // Colour bar with the value scale.
  const double bx = right + 25.0, bw = 18.0;
  for (int k = 0; k < 64; ++k) {
    const double y0 = bottom - map_h * (k + 1) / 64.0;
    svg += fmt::format("<rect x=\"{:.2f}\" y=\"{:.2f}\" width=\"{:.2f}\" height=\"{:.2f}\" fill=\"{}\"/>\n", bx, y0, bw,
                       map_h / 64.0 + 0.3, colour_of((k + 0.5) / 64.0));
  }
  svg += fmt::format("<rect x=\"{:.2f}\" y=\"{:.2f}\" width=\"{:.2f}\" height=\"{:.2f}\" fill=\"none\" stroke=\"black\"/>\n",
                     bx, top, bw, map_h);
  for (double t : scale.ticks) {
    const double y = bottom - (t - scale.lo) / (scale.hi - scale.lo) * map_h;
    svg += fmt::format("<line x1=\"{:.2f}\" y1=\"{:.2f}\" x2=\"{:.2f}\" y2=\"{:.2f}\" stroke=\"black\"/>\n", bx + bw, y,
                       bx + bw + 4, y);
    svg += fmt::format("<text x=\"{:.2f}\" y=\"{:.2f}\">{}</text>\n", bx + bw + 7, y + 4, tick_label(t, scale.step));
  }
  svg += fmt::format("<text x=\"{:.2f}\" y=\"{:.2f}\" text-anchor=\"middle\">{}</text>\n", bx + bw / 2, top - 8,
                     escape(value_label));
  for (std::size_t i = 0; i < notes.size(); ++i)
    svg += fmt::format("<text x=\"{:.2f}\" y=\"{:.2f}\">{}</text>\n", left, bottom + 64 + 18.0 * static_cast<double>(i),
                       escape(notes[i]));
  svg += "</svg>\n";
  write_file_atomically(path, [&](std::ostream& os) { os << svg; });
}

}  // namespace mesodpd
