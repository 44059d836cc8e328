// Positions in: every accepted form, held in named variables, gives identical contacts; the
// forms that would leave a view dangling do not compile.
#include <mccd/geometry/positions.h>

#include <gtest/gtest.h>

#include <type_traits>

#include <mccd/parallel/scene.h>
#include <mccd/geometry/error.h>

#include "fixtures/scenes.h"

using namespace mccd;

using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>;
using RowMajorF = Eigen::Matrix<float, Eigen::Dynamic, 3, Eigen::RowMajor>;

// Owning temporaries and expressions cannot become a view (it would outlive them).
static_assert(std::is_constructible_v<PositionsView, const Positions&>);
static_assert(!std::is_constructible_v<PositionsView, Positions&&>);
static_assert(std::is_constructible_v<PositionsView, const Eigen::MatrixX3d&>);
static_assert(!std::is_constructible_v<PositionsView, Eigen::MatrixX3d&&>);
static_assert(!std::is_constructible_v<PositionsView, RowMajor&&>);
static_assert(!std::is_constructible_v<PositionsView, std::vector<double>&&>);
static_assert(!std::is_constructible_v<PositionsView, std::vector<float>&&>);
static_assert(!std::is_convertible_v<decltype(std::declval<Eigen::MatrixX3d>() * 2.0), PositionsView>);
static_assert(!std::is_convertible_v<decltype(std::declval<RowMajor>() + std::declval<RowMajor>()), PositionsView>);

TEST(PositionsView, ReadsEveryLayout) {
  Positions p = {Vec3(1, 2, 3), Vec3(4, 5, 6)};
  Eigen::MatrixX3d col(2, 3);
  col << 1, 2, 3, 4, 5, 6;
  RowMajor row = col;
  Eigen::MatrixX3f colf = col.cast<float>();
  std::vector<double> xyz = {1, 2, 3, 4, 5, 6};
  std::vector<float> xyzf = {1, 2, 3, 4, 5, 6};
  const Eigen::Map<const RowMajor> map(xyz.data(), 2, 3);
  for (const PositionsView& v : std::vector<PositionsView>{p, col, row, colf, xyz, xyzf, map,
                                                          PositionsView(xyz.data(), 2), PositionsView(xyzf.data(), 2)}) {
    ASSERT_EQ(v.rows(), 2u);
    ASSERT_EQ(v.cols(), 3u);
    EXPECT_EQ(v.point(1), Vec3(4, 5, 6));
    EXPECT_EQ(v(0, 2), 3.0);
  }
  EXPECT_TRUE(PositionsView(p).is_dense_double());
  EXPECT_FALSE(PositionsView(col).is_dense_double());
  EXPECT_TRUE(PositionsView(colf).is_float());
}

TEST(PositionsView, EveryFormGivesTheSameContacts) {
  const AnimatedScene s = make_folding_cloth(30, 12);
  const std::size_t n = s.meshes[0].num_vertices();
  Scene reference(s.meshes);
  for (std::size_t f = 1; f < s.frames.size(); ++f) {
    const Positions& a = s.frames[f - 1][0];
    const Positions& b = s.frames[f][0];
    const StepResult ref = reference.step(a, b);
    // named copies of both ends in every accepted form
    const RowMajor row_a = a.mat(), row_b = b.mat();
    const Eigen::MatrixX3d col_a = a.mat(), col_b = b.mat();
    const std::vector<double> xyz_a = a.xyz(), xyz_b = b.xyz();
    const Eigen::Map<const RowMajor> map_a(xyz_a.data(), Eigen::Index(n), 3), map_b(xyz_b.data(), Eigen::Index(n), 3);
    // float: the step converts; contacts are compared against a double scene of the same floats
    const Eigen::MatrixX3f flt_a = a.mat().cast<float>(), flt_b = b.mat().cast<float>();
    const std::vector<PositionsView> starts = {row_a, col_a, xyz_a, map_a, PositionsView(xyz_a.data(), n)};
    const std::vector<PositionsView> ends = {row_b, col_b, xyz_b, map_b, PositionsView(xyz_b.data(), n)};
    for (std::size_t k = 0; k < starts.size(); ++k) {
      Scene sc(s.meshes);
      EXPECT_EQ(sc.step(starts[k], ends[k]).contacts, ref.contacts) << "form " << k << " step " << f;
    }
    const Positions fa(flt_a.cast<double>()), fb(flt_b.cast<double>());
    Scene from_float(s.meshes), from_double(s.meshes);
    EXPECT_EQ(from_float.step(flt_a, flt_b).contacts, from_double.step(fa, fb).contacts) << "float step " << f;
  }
}

TEST(PositionsView, WrongShapeIsRefused) {
  const AnimatedScene s = make_folding_cloth(6, 2);
  Scene sc(s.meshes);
  const std::size_t n = s.meshes[0].num_vertices();
  Eigen::MatrixXd four(Eigen::Index(n), 4);
  four.setZero();
  const Positions& ok = s.frames[0][0];
  EXPECT_THROW(sc.step(ok, four), Error);
  Eigen::MatrixX3d shorter(Eigen::Index(n - 1), 3);
  shorter.setZero();
  EXPECT_THROW(sc.step(shorter, ok), Error);
  EXPECT_THROW(sc.step(PositionsView(static_cast<const double*>(nullptr), n), ok), Error);
}
