// Minimal dependency-free SVG line/scatter plot, so every run can leave a picture of its result.
#pragma once
#include <string>
#include <vector>

namespace mesodpd {

struct SvgSeries {
  std::vector<double> x, y;
  std::vector<double> yerr;  // empty, or one half-width per point (NaN or <= 0 draws no bar)
  std::string label;         // legend text; empty leaves the series out of the legend
  std::string color;         // any SVG colour; empty picks from a built-in palette
  bool line = true;
  bool markers = false;
};

// Writes a self-contained SVG file with a framed axis box, "nice" 1-2-5 ticks with labels, light
// grid, error bars, a legend and one text line per note under the plot. Non-finite points are
// skipped. Text is XML-escaped, so labels may contain any UTF-8 (e.g. "±", "η").
// Throws std::runtime_error if the file cannot be written, std::invalid_argument if a series has
// x and y (or a non-empty yerr) of different lengths.
void write_svg_plot(const std::string& path, const std::string& title, const std::string& xlabel,
                    const std::string& ylabel, const std::vector<SvgSeries>& series,
                    const std::vector<std::string>& notes = {});

}  // namespace mesodpd
