#pragma once
/// @file How `mccd` prints a time of impact: in frame time (k + t for local time t in [0, 1]
/// of the step from frame k to k + 1), with the digits the time within the step needs, so
/// that an impact just after a frame never reads as the frame itself.
#include <string>

namespace mccd::cli {

/// A frame time k + t (k = floor, t in [0, 1)) as text:
/// - "-" for +infinity (no impact); the plain number for k + 0 ("0", "3");
/// - t >= 1e-3: decimals up to 4 significant digits of t, trailing zeros dropped ("0.0625",
///   "3.5", "12.00125"), never rounded up to the next frame ("3.99999", not "4");
/// - t < 1e-3: t in scientific notation, 3 significant digits, after "k + " when k > 0
///   ("7.49e-6", "3 + 7.49e-6").
/// Negative or non-finite times other than +infinity are printed with %g.
std::string impact_text(double frame_time);

}  // namespace mccd::cli
