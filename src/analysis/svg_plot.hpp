// Minimal dependency-free SVG line/scatter plots and colour maps, so every run can leave a picture of
// its result. Files are written atomically (io/atomic_file.hpp).
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

// A regular grid of values over [x0, x1] x [y0, y1]: nx x ny cells, x fastest; NaN = no value.
struct SvgGrid {
  std::size_t nx = 0, ny = 0;
  double x0 = 0, x1 = 1, y0 = 0, y1 = 1;
  std::vector<double> values;
};

// Writes a colour map of `grid` (viridis; grey where a value is not finite) with axes, a colour bar
// labelled `value_label` and one text line per note. Throws std::invalid_argument on a malformed grid.
void write_svg_map(const std::string& path, const std::string& title, const std::string& xlabel,
                   const std::string& ylabel, const SvgGrid& grid, const std::string& value_label,
                   const std::vector<std::string>& notes = {});

}  // namespace mesodpd
