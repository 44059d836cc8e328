// How `mccd run` prints a time of impact (tools/time_text.h): the time within the step keeps
// its significant digits, an impact just after a frame never reads as the frame itself, and
// one just before the next frame is never rounded up to it.
#include "time_text.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

using mccd::cli::impact_text;

TEST(ImpactText, NoImpactAndWholeFrames) {
  EXPECT_EQ(impact_text(std::numeric_limits<double>::infinity()), "-");
  EXPECT_EQ(impact_text(0.0), "0");
  EXPECT_EQ(impact_text(3.0), "3");
  EXPECT_EQ(impact_text(120.0), "120");
}

TEST(ImpactText, SmallTimesInScientificNotation) {
  // the cloth-ball case of issue 36: 7.49e-6 of the first step used to print as 0.0000
  EXPECT_EQ(impact_text(7.4913e-6), "7.49e-6");
  EXPECT_EQ(impact_text(2.5e-5), "2.5e-5");
  EXPECT_EQ(impact_text(9.99e-4), "9.99e-4");
  EXPECT_EQ(impact_text(1e-300), "1e-300");
  // after frame k the time within the step is written apart, so that its digits survive
  EXPECT_EQ(impact_text(3 + 7.49e-6), "3 + 7.49e-6");
  EXPECT_EQ(impact_text(1000 + 1.25e-4), "1000 + 1.25e-4");
}

TEST(ImpactText, FourSignificantDigitsOfTheTimeWithinTheStep) {
  EXPECT_EQ(impact_text(0.0625), "0.0625");
  EXPECT_EQ(impact_text(0.5), "0.5");
  EXPECT_EQ(impact_text(3.5), "3.5");
  EXPECT_EQ(impact_text(4.019687), "4.01969");
  EXPECT_EQ(impact_text(0.123456), "0.1235");
  EXPECT_EQ(impact_text(12.00125), "12.00125");
  EXPECT_EQ(impact_text(0.001), "0.001");
}

TEST(ImpactText, NeverRoundedUpToTheNextFrame) {
  for (const double t : {0.99996, 0.999975, 0.9999999, 1 - 1e-12}) {
    for (const double k : {0.0, 1.0, 41.0}) {
      const std::string s = impact_text(k + t);
      EXPECT_EQ(std::floor(std::stod(s)), k) << s;
      EXPECT_LT(std::stod(s), k + 1) << s;
      EXPECT_EQ(s.find('e'), std::string::npos) << s;
    }
  }
  EXPECT_EQ(impact_text(1.99996), "1.99996");
}

TEST(ImpactText, ReadsBackWithinItsDigits) {
  // whatever the form, the time within the step read back from the text is within half a
  // unit of its last printed digit: 3 significant digits in scientific notation, 4 otherwise
  for (double t = 1e-9; t < 1; t *= 1.37)
    for (const double k : {0.0, 7.0}) {
      const std::string s = impact_text(k + t);
      const std::size_t plus = s.find(" + ");
      const bool scientific = s.find('e') != std::string::npos;
      EXPECT_EQ(scientific, t < 1e-3) << s;
      const double back = plus == std::string::npos ? std::stod(s) - k : std::stod(s.substr(plus + 3));
      EXPECT_NEAR(back, t, t * (scientific ? 5.01e-3 : 5.01e-4) + 1e-13) << s;
    }
}
