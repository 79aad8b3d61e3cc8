// json_number: JSON summary numbers read exactly as printf's %.8g wrote them before, and are valid JSON.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <string>

#include "io/json_number.hpp"

using mesodpd::json_number;

TEST(JsonNumber, HoldsTheValueThatPercentPoint8gWrites) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> exponent(-7.0, 7.0);
  int same_text = 0;
  const int n = 20000;
  for (int k = 0; k < n; ++k) {
    const double v = (k % 2 ? -1.0 : 1.0) * std::pow(10.0, exponent(rng));
    const std::string printf_text = fmt::format("{:.8g}", v), text = json_number(v).dump();
    // The same double as the 8-digit text, always.
    ASSERT_EQ(nlohmann::json::parse(text).get<double>(), std::strtod(printf_text.c_str(), nullptr))
        << "value " << fmt::format("{:.17g}", v) << " written " << text;
    same_text += text == printf_text;
  }
  // The same text too, except where nlohmann's Grisu2 misses the shortest spelling (about 1 in 1,200).
  EXPECT_GT(same_text, n - n / 200);
  for (const double v : {0.0, 3.0, 4.5, 0.02, 2.0, -7.0, 1e-5, 1.25e-4, 1e-4, 2.5722156, 0.95734234, 123.5})
    EXPECT_EQ(json_number(v).dump(), fmt::format("{:.8g}", v));
}

TEST(JsonNumber, NonFiniteBecomesNull) {
  EXPECT_EQ(json_number(std::numeric_limits<double>::quiet_NaN()).dump(), "null");
  EXPECT_EQ(json_number(std::numeric_limits<double>::infinity()).dump(), "null");
  // printf would write "nan", which no JSON reader accepts.
  EXPECT_EQ(fmt::format("{:.8g}", std::numeric_limits<double>::quiet_NaN()), "nan");
}
