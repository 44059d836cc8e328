#pragma once
/// @file Vertex positions: an owning array (`Positions`) and a non-owning view of the caller's
/// own arrays (`PositionsView`), the forms a step accepts.
///
/// ABI safety: no public type owns Eigen dynamic storage. `Positions` keeps its numbers in a
/// `std::vector<double>`, so memory allocated on one side of the library boundary is freed
/// with the same allocator on the other, whatever flags (`-march=native`, sanitizers) the host
/// was built with. Eigen appears only as fixed-size `Vec3` (24 bytes, no alignment
/// requirement) and as `Eigen::Map` views over those vectors.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstddef>
#include <cstdint>
#include <initializer_list>
#include <type_traits>
#include <vector>

namespace mccd {

using Vec3 = Eigen::Vector3d;
/// The row-major n x 3 matrix type that `Positions::mat()` maps.
using PositionsMatrix = Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>;

/// Vertex positions, one (x, y, z) per vertex, interleaved in one `std::vector<double>`.
class Positions {
 public:
  Positions() = default;
  /// `rows` vertices at the origin.
  explicit Positions(std::size_t rows) : xyz_(3 * rows, 0.0) {}
  /// From interleaved coordinates (x0, y0, z0, x1, ...); the size must be a multiple of 3
  /// (the remainder is dropped).
  static Positions from_xyz(std::vector<double> xyz) {
    Positions p;
    xyz.resize(xyz.size() / 3 * 3);
    p.xyz_ = std::move(xyz);
    return p;
  }
  Positions(std::initializer_list<Vec3> points) {
    xyz_.reserve(3 * points.size());
    for (const Vec3& v : points) xyz_.insert(xyz_.end(), {v.x(), v.y(), v.z()});
  }
  /// Copies any n x 3 Eigen matrix or expression (any layout, double or float).
  template <class Derived>
  explicit Positions(const Eigen::MatrixBase<Derived>& m) : xyz_(3 * static_cast<std::size_t>(m.rows())) {
    for (Eigen::Index i = 0; i < m.rows(); ++i)
      for (Eigen::Index k = 0; k < 3; ++k) xyz_[3 * i + k] = static_cast<double>(m(i, k));
  }

  std::size_t rows() const { return xyz_.size() / 3; }
  bool empty() const { return xyz_.empty(); }
  void resize(std::size_t rows) { xyz_.resize(3 * rows, 0.0); }
  double* data() { return xyz_.data(); }
  const double* data() const { return xyz_.data(); }
  double& operator()(std::size_t i, int k) { return xyz_[3 * i + static_cast<std::size_t>(k)]; }
  double operator()(std::size_t i, int k) const { return xyz_[3 * i + static_cast<std::size_t>(k)]; }
  /// Vertex i as a vector (a copy).
  Vec3 point(std::size_t i) const { return {xyz_[3 * i], xyz_[3 * i + 1], xyz_[3 * i + 2]}; }
  void set_point(std::size_t i, const Vec3& p) {
    xyz_[3 * i] = p.x(), xyz_[3 * i + 1] = p.y(), xyz_[3 * i + 2] = p.z();
  }
  /// The array as an n x 3 row-major Eigen matrix, for Eigen arithmetic in place.
  Eigen::Map<PositionsMatrix> mat() { return {xyz_.data(), static_cast<Eigen::Index>(rows()), 3}; }
  Eigen::Map<const PositionsMatrix> mat() const { return {xyz_.data(), static_cast<Eigen::Index>(rows()), 3}; }
  const std::vector<double>& xyz() const { return xyz_; }
  std::vector<double>& xyz() { return xyz_; }

  friend bool operator==(const Positions& a, const Positions& b) { return a.xyz_ == b.xyz_; }

 private:
  std::vector<double> xyz_;
};

/// A read-only view of one mesh's positions in the caller's memory: n rows of (x, y, z), as
/// double or float, with any row and column stride. Nothing is copied when a view is made.
///
/// Accepted (each stays the caller's, and must outlive the call that reads the view):
///  - `Positions` (interleaved doubles);
///  - any Eigen matrix with 3 columns, double or float, row- or column-major
///    (`Eigen::MatrixX3d`, `Eigen::Matrix<double, Dynamic, 3, RowMajor>`, `Eigen::MatrixX3f`,
///    `Eigen::MatrixXd` with 3 columns);
///  - an `Eigen::Map` of such a matrix over the caller's buffer (a temporary `Map` is fine:
///    the memory is the caller's);
///  - `std::vector<double>` / `std::vector<float>` holding x, y, z interleaved;
///  - a pointer and a vertex count (`PositionsView(ptr, n)`, interleaved double or float).
/// Refused at compile time: temporaries of owning types (`PositionsView(Positions(...))`,
/// an Eigen matrix returned by value) and Eigen expressions (`a + b`), whose storage would die
/// before the view is read; store the array in a named variable first.
///
/// What the step does with it: it reads each view once, converting float to double, into the
/// scene's own arrays (which keep the last end positions for `advance()`); no form makes any
/// other copy.
class PositionsView {
 public:
  /// No positions (0 rows): what a step takes for a static mesh.
  PositionsView() = default;
  PositionsView(const Positions& p) : PositionsView(p.data(), p.rows()) {}  // NOLINT: implicit by design
  PositionsView(Positions&&) = delete;

  template <class Derived>
  PositionsView(const Eigen::PlainObjectBase<Derived>& m)  // NOLINT: implicit by design
      : PositionsView(m.data(), m.rows(), m.cols(), m.rowStride(), m.colStride()) {}
  template <class Derived>
  PositionsView(const Eigen::PlainObjectBase<Derived>&& m) = delete;

  template <class M, int Options, class Stride>
  PositionsView(const Eigen::Map<M, Options, Stride>& m)  // NOLINT: implicit by design
      : PositionsView(m.data(), m.rows(), m.cols(), m.rowStride(), m.colStride()) {}

  PositionsView(const std::vector<double>& xyz) : PositionsView(xyz.data(), xyz.size() / 3) {}  // NOLINT
  PositionsView(std::vector<double>&&) = delete;
  PositionsView(const std::vector<float>& xyz) : PositionsView(xyz.data(), xyz.size() / 3) {}  // NOLINT
  PositionsView(std::vector<float>&&) = delete;

  /// `rows` vertices at `xyz` (x, y, z interleaved).
  PositionsView(const double* xyz, std::size_t rows) : data_(xyz), rows_(rows), row_stride_(3), col_stride_(1) {}
  PositionsView(const float* xyz, std::size_t rows)
      : data_(xyz), rows_(rows), row_stride_(3), col_stride_(1), is_float_(true) {}

  std::size_t rows() const { return rows_; }
  /// Columns of the viewed array (3 for every valid view; a step refuses anything else).
  std::size_t cols() const { return cols_; }
  bool is_float() const { return is_float_; }
  /// Whether the numbers are x, y, z interleaved doubles (read in one pass, no conversion).
  bool is_dense_double() const { return !is_float_ && row_stride_ == 3 && col_stride_ == 1; }
  double operator()(std::size_t i, int k) const {
    const std::ptrdiff_t at = static_cast<std::ptrdiff_t>(i) * row_stride_ + k * col_stride_;
    return is_float_ ? static_cast<double>(static_cast<const float*>(data_)[at])
                     : static_cast<const double*>(data_)[at];
  }
  Vec3 point(std::size_t i) const { return {(*this)(i, 0), (*this)(i, 1), (*this)(i, 2)}; }
  const void* data() const { return data_; }

 private:
  template <class Scalar>
  PositionsView(const Scalar* data, Eigen::Index rows, Eigen::Index cols, Eigen::Index row_stride,
                Eigen::Index col_stride)
      : data_(data),
        rows_(static_cast<std::size_t>(rows)),
        cols_(static_cast<std::size_t>(cols)),
        row_stride_(row_stride),
        col_stride_(col_stride),
        is_float_(std::is_same_v<std::remove_const_t<Scalar>, float>) {
    static_assert(std::is_same_v<std::remove_const_t<Scalar>, double> ||
                      std::is_same_v<std::remove_const_t<Scalar>, float>,
                  "PositionsView: positions must be double or float");
  }

  const void* data_ = nullptr;
  std::size_t rows_ = 0, cols_ = 3;
  std::ptrdiff_t row_stride_ = 3, col_stride_ = 1;
  bool is_float_ = false;
};

}  // namespace mccd
