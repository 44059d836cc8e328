#pragma once
/// @file Reader for the elementary CCD query files of the public CCD benchmarks
/// (Wang et al. 2021 sample queries, Belgrod et al. 2023 Time-of-Impact data set).
///
/// Format: CSV, 8 rows per query, each row `xnum,xden,ynum,yden,znum,zden[,truth]`: one point
/// as three rationals, plus (7-column files) the ground truth, identical on the 8 rows of a
/// query (1 = the primitives touch at some t in [0, 1]). Row order:
///   edge-edge:   ea0_t0, ea1_t0, eb0_t0, eb1_t0, ea0_t1, ea1_t1, eb0_t1, eb1_t1
///   vertex-face: v_t0,   f0_t0,  f1_t0,  f2_t0,  v_t1,   f0_t1,  f1_t1,  f2_t1
/// which is exactly the layout of CcdPoints (start[0..3], end[0..3]).
///
/// Every denominator must be a positive power of two and every value exactly representable
/// as a double; the conversion is exact. Integers have at most kMaxRationalDigits digits
/// (leading zeros included), which every double's reduced form fits in. Lines end in "\n",
/// "\r\n" or "\r". Anything else is refused with mccd::Error naming the file and the line,
/// quoting at most the first 40 characters of an offending field.
#include <cstddef>
#include <string>
#include <vector>

#include <mccd/geometry/ccd.h>

namespace mccd {

/// The most digits a numerator or denominator may have: a double's reduced form needs at
/// most 309 (numerator, < 2^1024) and 324 (denominator, 2^1074). Longer integers are
/// refused before any conversion work.
inline constexpr std::size_t kMaxRationalDigits = 400;

struct CcdQuery {
  CcdPoints points;
  int truth = -1;  ///< 1 collides, 0 does not, -1 unknown (6-column file)
};

/// Reads every query of one CSV file. Throws mccd::Error("file:line: what") on malformed
/// input: wrong column count, a non-integer field, a denominator that is not a power of two,
/// a value not exactly representable as a double, a truth value that is not 0/1 or differs
/// within a query, a row count that is not a multiple of 8, mixed 6/7-column rows.
std::vector<CcdQuery> read_query_csv(const std::string& path);

/// Converts one rational given as decimal integer strings to a double, exactly.
/// Throws mccd::Error (message without location) when a field is not an integer of at most
/// kMaxRationalDigits digits, the denominator is not a positive power of two, or the value is
/// not exactly representable.
double rational_to_double(const std::string& numerator, const std::string& denominator);

}  // namespace mccd
