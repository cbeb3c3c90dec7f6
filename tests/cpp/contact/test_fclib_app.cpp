// The `./softpack fclib` executable: JSON lines, reaction files, exit status
// and messages naming the file.

#include "error.h"
#include "fclib_io.h"
#include "helpers.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <chrono>
#include <cstdio>
#include <fstream>
#include <sstream>

using namespace softpack::contact;
using namespace softpack::contact::test;

namespace
{
struct AppRun
{
  int status;
  std::vector<nlohmann::ordered_json> lines;
  std::string err;
  double wall_seconds; ///< from starting the command to its exit
};

/// Run softpack-fclib with arguments; stdout parsed line by line as JSON.
AppRun run_app(const std::string& args, const TempDir& dir)
{
  const std::filesystem::path err = dir.path() / "stderr.txt";
  const std::string cmd =
      std::string(SOFTPACK_FCLIB_APP) + " " + args + " 2>" + err.string();
  const auto start = std::chrono::steady_clock::now();
  FILE* pipe = ::popen(cmd.c_str(), "r");
  std::string out;
  char buffer[4096];
  while (std::fgets(buffer, sizeof(buffer), pipe))
    out += buffer;
  const int status = ::pclose(pipe);
  const std::chrono::duration<double> wall =
      std::chrono::steady_clock::now() - start;
  AppRun run{WIFEXITED(status) ? WEXITSTATUS(status) : -1, {}, {},
             wall.count()};
  std::istringstream lines(out);
  for (std::string line; std::getline(lines, line);)
    run.lines.push_back(nlohmann::ordered_json::parse(line));
  std::ifstream e(err);
  run.err.assign(std::istreambuf_iterator<char>(e), {});
  return run;
}
} // namespace

TEST(FclibApp, SolvesAndWritesReactions)
{
  TempDir dir;
  const std::string a = hdf5_file("FrictionContactProblem00071").string();
  const std::string b = hdf5_file("FrictionContactProblem00394").string();
  const AppRun run = run_app(a + " " + b + " --tol 1e-8 --solution-out " +
                                 (dir.path() / "out").string(),
                             dir);
  EXPECT_EQ(run.status, 0) << run.err;
  ASSERT_EQ(run.lines.size(), 2u);
  const nlohmann::ordered_json& j = run.lines[0];
  EXPECT_EQ(j["problem"], "FrictionContactProblem00071");
  EXPECT_EQ(j["contacts"], 89);
  EXPECT_GT(j["iterations"].get<int>(), 0);
  EXPECT_LE(j["error"].get<double>(), 1e-8);
  // The solve's own time: positive, and within the command's wall time (a
  // time in ms, or the process's whole life, would not be)
  EXPECT_GT(j["seconds"].get<double>(), 0.0);
  EXPECT_LT(j["seconds"].get<double>() + run.lines[1]["seconds"].get<double>(),
            run.wall_seconds);
  std::printf("fclib app: solve %.2e s, %.2e s; command %.2e s\n",
              j["seconds"].get<double>(), run.lines[1]["seconds"].get<double>(),
              run.wall_seconds);
  EXPECT_EQ(j["converged"], true);
  std::vector<std::string> keys;
  for (const auto& item : j.items())
    keys.push_back(item.key());
  EXPECT_EQ(keys, (std::vector<std::string>{"problem", "contacts", "iterations",
                                            "error", "seconds", "converged"}));

  std::ifstream csv(dir.path() / "out" / "FrictionContactProblem00071.r.csv");
  std::vector<double> r;
  for (double v; csv >> v;)
    r.push_back(v);
  ASSERT_EQ(r.size(), 178u);
  // The reactions written are the solution: their error is the one
  // reported (measured equal to the last bit, 2026-12-03: the file keeps
  // every digit)
  const FrictionContactProblem2D p = read_fclib_local(a);
  std::vector<double> u(r.size());
  EXPECT_NEAR(compute_error(p, r, u, 0.0).value, j["error"].get<double>(),
              1e-12 * j["error"].get<double>());
  EXPECT_TRUE(std::filesystem::exists(dir.path() / "out" /
                                      "FrictionContactProblem00394.r.csv"));
}

TEST(FclibApp, NonConvergenceExitsNonZero)
{
  TempDir dir;
  const std::string f =
      hdf5_file("fc2d_granularflowonwall_02020_00213").string();
  const AppRun run = run_app(f + " --tol 1e-8 --max-iter 50", dir);
  EXPECT_NE(run.status, 0);
  ASSERT_EQ(run.lines.size(), 1u);
  EXPECT_EQ(run.lines[0]["converged"], false);
  EXPECT_EQ(run.lines[0]["iterations"], 50);
  EXPECT_NE(run.err.find(f), std::string::npos) << run.err;
  EXPECT_NE(run.err.find("not converged"), std::string::npos) << run.err;
}

TEST(FclibApp, InvalidFileExitsNonZeroNamingIt)
{
  TempDir dir;
  const std::filesystem::path bad = dir.path() / "bad.hdf5";
  std::ofstream(bad) << "not hdf5";
  const std::string good = hdf5_file("FrictionContactProblem00031").string();
  const AppRun run = run_app(bad.string() + " " + good, dir);
  EXPECT_NE(run.status, 0);
  ASSERT_EQ(run.lines.size(), 1u); // the valid file is still solved
  EXPECT_EQ(run.lines[0]["problem"], "FrictionContactProblem00031");
  EXPECT_NE(run.err.find(bad.string() + ": not an HDF5 file"),
            std::string::npos)
      << run.err;
}

TEST(FclibApp, DescribesAProblemInsteadOfSolvingIt)
{
  TempDir dir;
  const std::string f = hdf5_file("FrictionContactProblem00071").string();
  const AppRun run = run_app(f + " --describe", dir);
  ASSERT_EQ(run.status, 0) << run.err;
  ASSERT_EQ(run.lines.size(), 1u);
  const nlohmann::ordered_json& line = run.lines[0];
  EXPECT_EQ(line["problem"], "FrictionContactProblem00071");
  EXPECT_FALSE(line.contains("iterations"));
  // the strength counts fall with the threshold, from every stored block
  const std::size_t blocks = line["offdiagonal_blocks"];
  std::size_t previous = blocks;
  for (const auto& [threshold, count] : line["blocks_at_or_above"].items())
  {
    EXPECT_LE(count.get<std::size_t>(), previous) << threshold;
    previous = count;
  }
  EXPECT_EQ(line["blocks_at_or_above"].size(), 8u);
}
