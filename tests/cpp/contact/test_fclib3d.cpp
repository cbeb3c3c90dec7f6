// The 3D problems of ../shared/data/fclib3d (Siconos' test data): read from
// Siconos text (.dat) and FCLIB HDF5 (local, and global condensed), solved
// by the one NLGS, the answer checked by Siconos' own fc3d_compute_error
// and compared with Siconos' fc3d NSGS. The small problems only (seconds);
// the granular ones are in docs/contact_3d.md.

#include "error.h"
#include "fclib_io.h"
#include "helpers.h"
#include "nlgs.h"
#include "siconos_io.h"

#include <gtest/gtest.h>
#include <hdf5.h>

#include <cmath>
#include <type_traits>

#ifdef SOFTPACK_HAVE_SICONOS
#include "siconos_reference.h"
#endif

using namespace softpack::contact;
using namespace softpack::contact::test;

namespace
{
std::filesystem::path data3d(const std::string& file)
{
  return data_dir().parent_path() / "fclib3d" / file;
}

/// Solve from r = 0 with the defaults but the tolerance; r and u returned
NlgsResult solve(const FrictionContactProblem3D& p, std::vector<double>& r,
                 std::vector<double>& u, double tolerance, int sweeps = 10000)
{
  r.assign(3 * p.num_contacts(), 0.0);
  u.assign(r.size(), 0.0);
  NlgsOptions options;
  options.tolerance = tolerance;
  options.max_sweeps = sweeps;
  return solve_nlgs(p, r, u, options);
}
} // namespace

/// The small local problems in Siconos' text format
class Fclib3dSmall : public ::testing::TestWithParam<std::string>
{
};

TEST_P(Fclib3dSmall, SolvedTo1e8AndCheckedBySiconos)
{
  const std::filesystem::path file = data3d(GetParam() + ".dat");
  const FrictionContactProblem3D p = read_siconos_dat<3>(file);
  std::vector<double> r, u;
  const NlgsResult result = solve(p, r, u, 1e-8);
  EXPECT_TRUE(result.converged) << result.error;
  EXPECT_LE(result.error, 1e-8);
  // every reaction in its cone
  for (std::size_t a = 0; a < p.num_contacts(); ++a)
    EXPECT_LE(std::hypot(r[3 * a + 1], r[3 * a + 2]),
              p.friction[a] * r[3 * a] * (1 + 1e-12));
  const NaturalMapError mine = compute_error(p, r, u, 1e-12);
#ifdef SOFTPACK_HAVE_SICONOS
  // Siconos reads the same file itself and computes the error
  double theirs = -1;
  ASSERT_EQ(siconos_fc3d_error(file.c_str(), r.data(),
                               static_cast<int>(r.size()), &theirs),
            0);
  EXPECT_NEAR(theirs, mine.value, 1e-6 * mine.value + 1e-15);

  // Siconos' NSGS to the same tolerance: the same reactions within the
  // tolerance's reach
  std::vector<double> rs(r.size()), us(r.size());
  SiconosFc2dResult sr{};
  ASSERT_EQ(siconos_fc3d_nsgs(file.c_str(), 1e-10, 10000, rs.data(), us.data(),
                              static_cast<int>(rs.size()), &sr),
            0);
  double d = 0;
  for (std::size_t k = 0; k < r.size(); ++k)
    d += (r[k] - rs[k]) * (r[k] - rs[k]);
  EXPECT_LT(std::sqrt(d), 1e-5 * mine.scale) << "Siconos info " << sr.info;
#else
  ADD_FAILURE() << "Siconos numerics not found";
#endif
}

INSTANTIATE_TEST_SUITE_P(Data, Fclib3dSmall,
                         ::testing::Values("FrictionContact3D_1c",
                                           "FC3D_Example1", "Rover4144",
                                           "NESpheres_10_1"));

TEST(Fclib3dRead, TheOneContactProblemAsWritten)
{
  const FrictionContactProblem3D p =
      read_siconos_dat<3>(data3d("FrictionContact3D_1c.dat"));
  ASSERT_EQ(p.num_contacts(), 1u);
  Eigen::Matrix3d W;
  W << 15, -1, -2, -1, 14, 1, -2, 1, 16;
  EXPECT_EQ(p.W.diagonal(0), W);
  EXPECT_EQ(p.q, (std::vector<double>{-1, 2, 3}));
  EXPECT_EQ(p.friction, std::vector<double>{0.1});
}

TEST(Fclib3dRead, SiconosTextAndHdf5GiveThe2DProblemsBitForBit)
{
  // The 2D set has both copies: the text reader's dense (storage 0) and
  // sparse-block (storage 1) problems against the HDF5 reader's
  for (const std::string name :
       {"FC2D_SliderCrankLagrangian00000", "FrictionContactProblem00031",
        "FrictionContactProblem00071", "FrictionContactProblem00237",
        "FrictionContactProblem00374"})
  {
    const FrictionContactProblem2D text =
        read_siconos_dat<2>(data_dir() / "siconos_dat" / (name + ".dat"));
    const FrictionContactProblem2D h5 = read_fclib_local(hdf5_file(name));
    EXPECT_EQ(text.q, h5.q) << name;
    EXPECT_EQ(text.friction, h5.friction) << name;
    EXPECT_EQ(to_dense(text.W), to_dense(h5.W)) << name;
  }
}

TEST(Fclib3dRead, RefusesOtherDimensionsAndCsparseText)
{
  EXPECT_THROW(read_siconos_dat<2>(data3d("FC3D_Example1.dat")), FclibError);
  EXPECT_THROW(read_fclib_file<2>(data3d("Box_Stacks-i0122-82-5.hdf5")),
               FclibError);
  try
  {
    read_siconos_dat<2>(data_dir() / "siconos_dat" /
                        "fc2d_granularflowonwall_00667_00000.dat");
    ADD_FAILURE() << "storage 2 read";
  }
  catch (const FclibError& e)
  {
    EXPECT_NE(std::string(e.what()).find("storage 2"), std::string::npos);
  }
}

namespace
{
/// One dataset of /fclib_global
template <typename T>
void write(hid_t file, const std::string& name, const std::vector<T>& v)
{
  const hid_t type =
      std::is_same_v<T, int> ? H5T_NATIVE_INT : H5T_NATIVE_DOUBLE;
  const hsize_t n = v.size();
  hid_t space = H5Screate_simple(1, &n, nullptr);
  hid_t set = H5Dcreate2(file, ("/fclib_global/" + name).c_str(), type, space,
                         H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  H5Dwrite(set, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data());
  H5Dclose(set);
  H5Sclose(space);
}

std::vector<double> values(const Eigen::MatrixXd& m)
{
  return {m.data(), m.data() + m.size()};
}

/// A global problem with 6 velocities and 2 contacts: M diagonal (as
/// triplets), H dense (as compressed columns)
void write_global(const std::filesystem::path& path, const Eigen::MatrixXd& H,
                  const Eigen::VectorXd& m, const Eigen::VectorXd& f,
                  const Eigen::VectorXd& w)
{
  hid_t file = H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
  for (const char* g : {"", "/M", "/H", "/vectors"})
    H5Gclose(H5Gcreate2(file, (std::string("/fclib_global") + g).c_str(),
                        H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT));
  write(file, "spacedim", std::vector<int>{3});
  for (const std::string M : {"M/", "H/"})
    for (const char* k : {"m", "n"})
      write(file, M + k, std::vector<int>{6});
  write(file, "M/nz", std::vector<int>{6});
  write(file, "M/nzmax", std::vector<int>{6});
  write(file, "M/i", std::vector<int>{0, 1, 2, 3, 4, 5});
  write(file, "M/p", std::vector<int>{0, 1, 2, 3, 4, 5}); // triplets: column
  write(file, "M/x", values(m));
  write(file, "H/nz", std::vector<int>{-1});
  write(file, "H/nzmax", std::vector<int>{36});
  write(file, "H/p", std::vector<int>{0, 6, 12, 18, 24, 30, 36});
  std::vector<int> rows;
  for (int k = 0; k < 36; ++k)
    rows.push_back(k % 6);
  write(file, "H/i", rows);
  write(file, "H/x", values(H));
  write(file, "vectors/f", values(f));
  write(file, "vectors/w", values(w));
  write(file, "vectors/mu", std::vector<double>{0.3, 0.5});
  H5Fclose(file);
}
} // namespace

TEST(Fclib3dGlobal, CondensedAsHTransposeMInverseH)
{
  // W and q of a hand-written global problem against a dense computation
  // of H^T M^-1 H and H^T M^-1 f + w
  TempDir dir;
  const std::filesystem::path path = dir.path() / "global.hdf5";
  Eigen::MatrixXd H(6, 6);
  for (int k = 0; k < 36; ++k)
    H(k % 6, k / 6) = std::sin(1.0 + k) + (k % 7 == 0 ? 2.0 : 0.0);
  const Eigen::VectorXd m = (Eigen::VectorXd(6) << 2, 2, 2, 4, 4, 5).finished();
  const Eigen::VectorXd f = Eigen::VectorXd::LinSpaced(6, -1, 1);
  const Eigen::VectorXd w = Eigen::VectorXd::LinSpaced(6, 0.5, -0.7);
  write_global(path, H, m, f, w);

  const FrictionContactProblem3D p = read_fclib_file<3>(path).problem;
  const Eigen::MatrixXd Minv = m.cwiseInverse().asDiagonal();
  const Eigen::MatrixXd W = H.transpose() * Minv * H;
  const Eigen::VectorXd q = H.transpose() * Minv * f + w;
  for (int a = 0; a < 2; ++a)
  {
    EXPECT_LT((p.W.diagonal(a) - W.block<3, 3>(3 * a, 3 * a)).norm(),
              1e-14 * W.norm());
    ASSERT_EQ(p.W.row_blocks(a).size(), 1u);
    EXPECT_LT((p.W.row_blocks(a)[0] - W.block<3, 3>(3 * a, 3 - 3 * a)).norm(),
              1e-14 * W.norm());
  }
  for (int k = 0; k < 6; ++k)
    EXPECT_NEAR(p.q[k], q[k], 1e-14 * q.norm());
  EXPECT_EQ(p.friction, (std::vector<double>{0.3, 0.5}));
}

TEST(Fclib3dGlobal, SolvedTo1e8)
{
  const FclibFile3D f =
      read_fclib_file<3>(data3d("Box_Stacks-i0122-82-5.hdf5"));
  std::vector<double> r, u;
  const NlgsResult result = solve(f.problem, r, u, 1e-8);
  EXPECT_TRUE(result.converged) << result.error << " " << result.iterations;
}

TEST(Fclib3dGlobal, RelaxedSplitAndAlternateSweepsToo)
{
  // The 2D solver's levers on a 3D problem: over-relaxation 1.8 (projected
  // on the circular cone), the alternate order, the split sweep on one and
  // two threads (the same bits)
  const FrictionContactProblem3D p =
      read_fclib_file<3>(data3d("Box_Stacks-i0122-82-5.hdf5")).problem;
  NlgsOptions options;
  options.relaxation = 1.8;
  options.order = SweepOrder::alternate;
  options.split_min_contacts = 1;
  std::vector<std::vector<double>> answers;
  for (const int threads : {1, 2})
  {
    options.threads = threads;
    std::vector<double> r(3 * p.num_contacts(), 0.0), u(r.size());
    const NlgsResult result = solve_nlgs(p, r, u, options);
    EXPECT_TRUE(result.converged) << result.error;
    EXPECT_LE(compute_error(p, r, u, 1e-12).value, 1e-8);
    for (std::size_t a = 0; a < p.num_contacts(); ++a)
      EXPECT_LE(std::hypot(r[3 * a + 1], r[3 * a + 2]),
                p.friction[a] * r[3 * a] * (1 + 1e-12));
    answers.push_back(r);
  }
  EXPECT_EQ(answers[0], answers[1]);
}

TEST(Fclib3dGlobal, VelocityUpdatedSweepsFollowTheRowSweeps)
{
  // NlgsUpdate::velocity (the 3D default) against NlgsUpdate::row: the same
  // Gauss–Seidel iteration apart from rounding (the same sweeps to one, the
  // reactions within the tolerance's reach), over-relaxed, alternate, split
  // on one and two threads (the same bits)
  for (const char* name : {"Box_Stacks-i0122-82-5.hdf5"})
  {
    const FrictionContactProblem3D p = read_fclib_file<3>(data3d(name)).problem;
    NlgsOptions options;
    options.tolerance = 1e-8;
    options.relaxation = 1.8;
    options.order = SweepOrder::alternate;
    options.split_min_contacts = 1;
    std::vector<std::vector<double>> answers;
    std::vector<int> sweeps;
    for (const NlgsUpdate update :
         {NlgsUpdate::row, NlgsUpdate::velocity, NlgsUpdate::velocity})
    {
      options.update = update;
      options.threads = answers.size() == 2 ? 2 : 1;
      std::vector<double> r(3 * p.num_contacts(), 0.0), u(r.size());
      const NlgsResult result = solve_nlgs(p, r, u, options);
      EXPECT_TRUE(result.converged) << result.error;
      EXPECT_LE(compute_error(p, r, u, 1e-12).value, 1e-8);
      answers.push_back(r);
      sweeps.push_back(result.iterations);
    }
    EXPECT_EQ(answers[1], answers[2]);
    EXPECT_EQ(sweeps[1], sweeps[2]);
    EXPECT_LE(std::abs(sweeps[0] - sweeps[1]), 1);
    double d = 0, n = 0;
    for (std::size_t k = 0; k < answers[0].size(); ++k)
    {
      d = std::max(d, std::abs(answers[0][k] - answers[1][k]));
      n = std::max(n, std::abs(answers[0][k]));
    }
    EXPECT_LT(d, 1e-6 * n) << name;
  }
}
