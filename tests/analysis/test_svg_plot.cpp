// Tests that the SVG plot writer produces well-formed markup carrying its labels.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "analysis/svg_plot.hpp"

namespace mesodpd {
namespace {

std::string read_file(const std::string& path) {
  std::ifstream is(path);
  std::stringstream ss;
  ss << is.rdbuf();
  return ss.str();
}

// A tiny XML well-formedness check: every opened element is closed in order, attribute values are
// quoted, and no bare '<' or '&' appears in text. Returns an empty string when fine.
std::string check_markup(const std::string& s) {
  std::vector<std::string> stack;
  std::size_t i = 0;
  while (i < s.size()) {
    if (s[i] == '&') {
      const std::size_t semi = s.find(';', i);
      const std::string ent = s.substr(i, semi == std::string::npos ? 1 : semi - i + 1);
      if (ent != "&amp;" && ent != "&lt;" && ent != "&gt;" && ent != "&quot;" && ent != "&apos;") {
        return "bad entity at " + std::to_string(i);
      }
      i += ent.size();
      continue;
    }
    if (s[i] != '<') {
      if (s[i] == '>') return "stray '>' at " + std::to_string(i);
      ++i;
      continue;
    }
    // Find the end of the tag, skipping quoted attribute values.
    std::size_t j = i + 1;
    char quote = 0;
    for (; j < s.size(); ++j) {
      if (quote) {
        if (s[j] == quote)
          quote = 0;
        else if (s[j] == '<')
          return "'<' inside attribute at " + std::to_string(j);
      } else if (s[j] == '"' || s[j] == '\'') {
        quote = s[j];
      } else if (s[j] == '>') {
        break;
      }
    }
    if (j == s.size()) return "unterminated tag at " + std::to_string(i);
    const std::string tag = s.substr(i + 1, j - i - 1);
    const bool closing = !tag.empty() && tag[0] == '/';
    const bool self_closing = !tag.empty() && tag.back() == '/';
    std::string name = tag.substr(closing ? 1 : 0);
    name = name.substr(0, name.find_first_of(" \t\n/"));
    if (name.empty()) return "empty tag name at " + std::to_string(i);
    if (closing) {
      if (stack.empty() || stack.back() != name) return "mismatched </" + name + "> at " + std::to_string(i);
      stack.pop_back();
    } else if (!self_closing) {
      stack.push_back(name);
    }
    i = j + 1;
  }
  if (!stack.empty()) return "unclosed <" + stack.back() + ">";
  return "";
}

TEST(SvgPlot, WellFormedWithLabels) {
  SvgSeries data{{0.25, 0.75, 1.25, 1.75},
                 {0.1, 0.4, -0.4, -0.1},
                 {0.02, 0.03, 0.02, 0.05},
                 "measured",
                 "",
                 false,
                 true};
  SvgSeries fit{{0.25, 0.75, 1.25, 1.75}, {0.12, 0.38, -0.38, -0.12}, {}, "fit", "#000000", true, false};
  const std::string path = ::testing::TempDir() + "plot_test.svg";
  write_svg_plot(path, "Reverse Poiseuille profile", "z", "v_x", {data, fit},
                 {"eta = 0.85 ± 0.01 (kinetic theory 0.96)", "blocks = 16"});
  const std::string svg = read_file(path);
  ASSERT_EQ(svg.rfind("<svg", 0), 0u);
  EXPECT_EQ(check_markup(svg), "");
  for (const char* text : {"Reverse Poiseuille profile", ">z<", ">v_x<", ">measured<", ">fit<",
                           "eta = 0.85 ± 0.01 (kinetic theory 0.96)", "blocks = 16"}) {
    EXPECT_NE(svg.find(text), std::string::npos) << text;
  }
  EXPECT_NE(svg.find("<polyline"), std::string::npos);
  EXPECT_NE(svg.find("<circle"), std::string::npos);
  // Round tick labels: the y range [-0.43, 0.43] gets 0.2 steps, so 0.0 and -0.4 are labelled.
  EXPECT_NE(svg.find(">0.0<"), std::string::npos);
  EXPECT_NE(svg.find(">-0.4<"), std::string::npos);
  EXPECT_EQ(svg.find("-0.0<"), std::string::npos);
}

TEST(SvgPlot, EscapesTextAndSurvivesOddData) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  SvgSeries odd{{1.0, 2.0, nan, 4.0}, {5.0, 5.0, 5.0, nan}, {}, "a < b & \"c\"", "", true, true};
  SvgSeries empty{{}, {}, {}, "", "", true, false};
  const std::string path = ::testing::TempDir() + "plot_odd.svg";
  write_svg_plot(path, "<title> & more", "x", "y", {odd, empty}, {"1 < 2"});
  const std::string svg = read_file(path);
  EXPECT_EQ(check_markup(svg), "");
  EXPECT_NE(svg.find("a &lt; b &amp; &quot;c&quot;"), std::string::npos);
  EXPECT_NE(svg.find("&lt;title&gt; &amp; more"), std::string::npos);
  EXPECT_EQ(svg.find("nan"), std::string::npos);

  write_svg_plot(path, "nothing", "x", "y", {});
  EXPECT_EQ(check_markup(read_file(path)), "");
}

TEST(SvgPlot, RejectsMismatchedSeries) {
  SvgSeries bad{{1.0, 2.0}, {1.0}, {}, "bad", "", true, false};
  EXPECT_THROW(write_svg_plot(::testing::TempDir() + "bad.svg", "t", "x", "y", {bad}), std::invalid_argument);
  SvgSeries bad_err{{1.0, 2.0}, {1.0, 2.0}, {0.1}, "bad", "", true, false};
  EXPECT_THROW(write_svg_plot(::testing::TempDir() + "bad.svg", "t", "x", "y", {bad_err}),
               std::invalid_argument);
  EXPECT_THROW(write_svg_plot("/nonexistent-dir/x.svg", "t", "x", "y", {}), std::runtime_error);
}

}  // namespace
}  // namespace mesodpd
