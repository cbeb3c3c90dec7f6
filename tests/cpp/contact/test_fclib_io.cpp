// FCLIB local files: malformed files (written here with the HDF5 C API, in a
// temporary directory) give errors naming the file and what is wrong; the
// dump of a problem reads back identical and replays.

#include "fclib_io.h"
#include "helpers.h"
#include "nlgs.h"

#include <gtest/gtest.h>
#include <hdf5.h>

#include <cmath>
#include <fstream>
#include <limits>
#include <set>

using namespace softpack::contact;
using namespace softpack::contact::test;

namespace
{
/// What to write: a valid 2-contact problem unless changed by a test.
struct Spec
{
  std::string group = "/fclib_local";
  std::set<std::string> omit; // datasets left out, e.g. "vectors/q"
  bool spacedim_as_double = false;
  int spacedim = 2;
  int m = 4, n = 4, nz = -2;
  std::vector<int> p = {0, 2, 4, 6, 8};
  std::vector<int> i = {0, 1, 0, 1, 2, 3, 2, 3};
  std::vector<double> x = {2, 0, 0, 1, 2, 0, 0, 1};
  std::vector<double> q = {-1, 0.1, -1, -0.2};
  std::vector<double> mu = {0.3, 0.3};
};

void write_dataset(hid_t file, const std::string& path, hid_t type,
                   const void* data, std::size_t size)
{
  const hsize_t dims[1] = {size};
  hid_t space = H5Screate_simple(1, dims, nullptr);
  hid_t set = H5Dcreate2(file, path.c_str(), type, space, H5P_DEFAULT,
                         H5P_DEFAULT, H5P_DEFAULT);
  if (size > 0)
    H5Dwrite(set, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data);
  H5Dclose(set);
  H5Sclose(space);
}

void write_file(const Spec& s, const std::filesystem::path& path)
{
  hid_t file = H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
  for (const std::string g : {"", "/W", "/vectors"})
    H5Gclose(H5Gcreate2(file, (s.group + g).c_str(), H5P_DEFAULT, H5P_DEFAULT,
                        H5P_DEFAULT));
  auto ints = [&](const std::string& name, const std::vector<int>& v)
  {
    if (!s.omit.count(name))
      write_dataset(file, s.group + "/" + name, H5T_NATIVE_INT, v.data(),
                    v.size());
  };
  auto doubles = [&](const std::string& name, const std::vector<double>& v)
  {
    if (!s.omit.count(name))
      write_dataset(file, s.group + "/" + name, H5T_NATIVE_DOUBLE, v.data(),
                    v.size());
  };
  if (s.spacedim_as_double)
    doubles("spacedim", {double(s.spacedim)});
  else
    ints("spacedim", {s.spacedim});
  ints("W/m", {s.m});
  ints("W/n", {s.n});
  ints("W/nz", {s.nz});
  ints("W/nzmax", {int(s.x.size())});
  ints("W/p", s.p);
  ints("W/i", s.i);
  doubles("W/x", s.x);
  doubles("vectors/q", s.q);
  doubles("vectors/mu", s.mu);
  H5Fclose(file);
}

class MalformedFile : public ::testing::Test
{
protected:
  /// Writes the spec and expects the reader to fail naming the file and
  /// the given part.
  void expect_error(const Spec& s, const std::string& part)
  {
    const std::filesystem::path path = _dir.path() / "problem.hdf5";
    write_file(s, path);
    expect_error(path, part);
  }

  void expect_error(const std::filesystem::path& path, const std::string& part)
  {
    try
    {
      read_fclib_local(path);
      ADD_FAILURE() << "no error for " << path << ", expected: " << part;
    }
    catch (const FclibError& e)
    {
      const std::string what = e.what();
      EXPECT_EQ(what.rfind(path.string(), 0), 0u) << what;
      EXPECT_NE(what.find(part), std::string::npos) << what;
    }
  }

  TempDir _dir;
};
} // namespace

TEST_F(MalformedFile, TheValidSpecReads)
{
  const std::filesystem::path path = _dir.path() / "good.hdf5";
  write_file(Spec{}, path);
  const FrictionContactProblem2D p = read_fclib_local(path);
  EXPECT_EQ(p.num_contacts(), 2u);
  EXPECT_EQ(p.W.diagonal(1)(0, 0), 2.0);
  EXPECT_EQ(p.W.num_offdiagonal_blocks(), 0u);
}

TEST_F(MalformedFile, NotAFileOrNotHdf5)
{
  expect_error(_dir.path() / "absent.hdf5", "no such file");
  const std::filesystem::path text = _dir.path() / "text.hdf5";
  std::ofstream(text) << "2\n2\n0\n";
  expect_error(text, "not an HDF5 file");
}

TEST_F(MalformedFile, MissingGroupOrGlobalProblem)
{
  Spec s;
  s.group = "/something_else";
  expect_error(s, "missing group /fclib_local");
  s.group = "/fclib_global";
  expect_error(s, "global problem");
}

TEST_F(MalformedFile, MissingDatasets)
{
  for (const std::string name :
       {"spacedim", "vectors/q", "vectors/mu", "W/m", "W/nz", "W/p", "W/x"})
  {
    Spec s;
    s.omit = {name};
    expect_error(s, "/fclib_local/" + name + ": missing");
  }
}

TEST_F(MalformedFile, Dimension3)
{
  Spec s;
  s.spacedim = 3;
  expect_error(s, "dimension 3");
  s.spacedim_as_double = true;
  s.spacedim = 2;
  expect_error(s, "spacedim: not an integer dataset");
}

TEST_F(MalformedFile, WrongSizes)
{
  Spec s;
  s.q.pop_back();
  expect_error(s, "vectors/q: 3 values, expected 4");
  s = Spec{};
  s.mu.push_back(0.3); // three contacts, W and q for two
  expect_error(s, "vectors/q: 4 values, expected 6");
  s = Spec{};
  s.m = 6;
  expect_error(s, "W is 6 x 4, expected 4 x 4");
  s = Spec{};
  s.p = {0, 2, 4, 6};
  expect_error(s, "W/p: 4 pointers, expected 5");
  s = Spec{};
  s.p = {0, 2, 1, 6, 8};
  expect_error(s, "pointers decrease");
  s = Spec{};
  s.x.resize(6);
  expect_error(s, "W has 8 nonzeros");
  s = Spec{};
  s.i[3] = 4;
  expect_error(s, "W/i: entry 3 = 4 outside [0, 4)");
  s = Spec{};
  s.nz = -3;
  expect_error(s, "nz = -3");
}

TEST_F(MalformedFile, NegativeMuAndNonFiniteValues)
{
  Spec s;
  s.mu[1] = -0.3;
  expect_error(s, "friction[1] = -0.300000 is negative");
  s = Spec{};
  s.q[2] = std::numeric_limits<double>::quiet_NaN();
  expect_error(s, "q[2] is not finite");
  s = Spec{};
  s.mu[0] = std::numeric_limits<double>::infinity();
  expect_error(s, "friction[0] is not finite");
  s = Spec{};
  s.x[3] = std::numeric_limits<double>::infinity();
  expect_error(s, "W entry (1, 1) is not finite");
}

TEST_F(MalformedFile, MissingDiagonalBlock)
{
  Spec s; // contact 1's rows point at contact 0's columns
  s.i = {0, 1, 0, 1, 0, 1, 0, 1};
  expect_error(s, "contact 1 has W_nn");
}

TEST_F(MalformedFile, OtherCsparseStoragesRead)
{
  // FCLIB also allows compressed columns (nz = -1) and triplets (nz >= 0)
  Spec s;
  write_file(s, _dir.path() / "csr.hdf5");
  s.nz = -1; // W is symmetric: its CSR arrays are also its CSC arrays
  write_file(s, _dir.path() / "csc.hdf5");
  EXPECT_EQ(to_dense(read_fclib_local(_dir.path() / "csc.hdf5").W),
            to_dense(read_fclib_local(_dir.path() / "csr.hdf5").W));

  s.nz = 3; // triplets: row i, column p
  s.i = {0, 2, 3};
  s.p = {0, 2, 1};
  s.x = {2, 3, 0.5};
  write_file(s, _dir.path() / "triplet.hdf5");
  Eigen::MatrixXd expected = Eigen::MatrixXd::Zero(4, 4);
  expected(0, 0) = 2;
  expected(2, 2) = 3;
  expected(3, 1) = 0.5;
  EXPECT_EQ(to_dense(read_fclib_local(_dir.path() / "triplet.hdf5").W),
            expected);
}

TEST(DumpProblem, WritesReadsBackAndReplays)
{
  TempDir dir;
  const FclibLocalFile original =
      read_fclib_local_file(hdf5_file("FrictionContactProblem00237"));
  const FrictionContactProblem2D& p = original.problem;
  const std::filesystem::path path = dir.path() / "dump.hdf5";
  std::vector<double> guess(2 * p.num_contacts(), 0.5);
  dump_problem(p, path, "round trip", guess);

  const FclibLocalFile back = read_fclib_local_file(path);
  EXPECT_EQ(back.title, "dump");
  EXPECT_EQ(back.problem.q, p.q);
  EXPECT_EQ(back.problem.friction, p.friction);
  EXPECT_EQ(to_dense(back.problem.W), to_dense(p.W));
  ASSERT_TRUE(back.guess_r);
  EXPECT_EQ(*back.guess_r, guess);

  std::vector<double> r1(guess.size(), 0.0), r2(r1), u(r1.size());
  const NlgsResult a = solve_nlgs(p, r1, u);
  const NlgsResult b = solve_nlgs(back.problem, r2, u);
  EXPECT_TRUE(b.converged);
  EXPECT_EQ(a.iterations, b.iterations);
  EXPECT_EQ(r1, r2);
}

TEST(DumpProblem, FailedSolveReplaysFromItsDump)
{
  // what the run loop does: the solver only returns its outcome; the caller
  // keeps the unsolved problem and its start (StepReport), writes them with
  // dump_problem, and a test replays them from the file
  TempDir dir;
  const FrictionContactProblem2D p =
      read_fclib_local(hdf5_file("FrictionContactProblem00071"));
  std::vector<double> r(2 * p.num_contacts(), 0.0), u(r.size());
  const std::vector<double> start = r;
  const NlgsResult failed = solve_nlgs(p, r, u, {.max_sweeps = 5});
  ASSERT_FALSE(failed.converged);

  const std::filesystem::path path = dir.path() / "failed_step_17.hdf5";
  dump_problem(p, path, "NLGS did not converge", start);
  const FclibLocalFile replay = read_fclib_local_file(path);
  ASSERT_TRUE(replay.guess_r);
  EXPECT_EQ(*replay.guess_r, start);
  std::vector<double> r2 = *replay.guess_r;
  NlgsResult again = solve_nlgs(replay.problem, r2, u, {.max_sweeps = 5});
  EXPECT_FALSE(again.converged);
  EXPECT_EQ(r2, r); // the same failure, bit for bit
  r2 = *replay.guess_r;
  again = solve_nlgs(replay.problem, r2, u);
  EXPECT_TRUE(again.converged);
}
