// softpack-fclib: solve frictional contact problems stored in the FCLIB
// HDF5 layout (2D: local; --dim 3: local or global, condensed) or in
// Siconos' text format (NAME.dat) with the simulator's own NLGS
// (softpack_contact), one solver for both dimensions.
//
//   softpack-fclib FILE... [--dim 2|3] [--tol T] [--max-iter N]
//                  [--solution-out DIR] [--extrapolate] [--describe]
//
// One JSON line per problem on stdout (with --describe, the problem's
// structure instead of a solve); messages on stderr. Exit status 1 if
// a file is not a valid problem of that dimension or a problem does not
// converge.

#include "fclib_io.h"
#include "frictionless_condensation.h"
#include "nlgs.h"
#include "problem_structure.h"
#include "siconos_io.h"

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <string>
#include <vector>

namespace contact = softpack::contact;

namespace
{
struct Arguments
{
  std::vector<std::string> files;
  contact::NlgsOptions options;
  std::string solution_out;
  bool from_guess = false;
  bool describe = false;
  bool condense = false;
  int dim = 2;
};

//-----------------------------------------------------------------------------
void write_reactions(const std::filesystem::path& file,
                     const std::vector<double>& r)
{
  std::ofstream out(file);
  char line[32];
  for (double v : r)
  {
    std::snprintf(line, sizeof(line), "%.17g\n", v);
    out << line;
  }
  if (!out)
    throw std::runtime_error(file.string() + ": cannot write");
}
//-----------------------------------------------------------------------------
/// The problem of a Siconos .dat file, or of an FCLIB HDF5 file (2D:
/// local only, as the simulator dumps them; 3D: local or global)
template <int D> contact::FclibFile<D> read_problem(const std::string& file)
{
  if (std::filesystem::path(file).extension() == ".dat")
  {
    contact::FclibFile<D> stored;
    stored.problem = contact::read_siconos_dat<D>(file);
    return stored;
  }
  if constexpr (D == 2)
    return contact::read_fclib_local_file(file);
  else
    return contact::read_fclib_file<D>(file);
}
//-----------------------------------------------------------------------------
/// One problem's ProblemStructure as a JSON line
template <int D>
void describe(const std::string& name,
              const contact::FrictionContactProblem<D>& problem)
{
  const contact::ProblemStructure s = contact::problem_structure(problem);
  nlohmann::ordered_json line;
  line["problem"] = name;
  line["contacts"] = s.contacts;
  line["offdiagonal_blocks"] = s.offdiagonal_blocks;
  nlohmann::ordered_json kept;
  for (std::size_t t = 0; t < s.coupling_thresholds.size(); ++t)
  {
    char key[16];
    std::snprintf(key, sizeof(key), "%.0e", s.coupling_thresholds[t]);
    kept[key] = s.blocks_at_or_above[t];
  }
  line["blocks_at_or_above"] = kept;
  line["frictionless"] = s.frictionless;
  line["frictionless_sets"] = s.frictionless_sets;
  line["set_sizes"] = {s.smallest_set, s.largest_set};
  line["set_scaled_eigenvalues"] = {s.scaled_eigenvalue_min,
                                    s.scaled_eigenvalue_max};
  std::cout << line.dump() << std::endl;
}
//-----------------------------------------------------------------------------
/// Solve (or describe) one file; returns false on an invalid file or no
/// convergence.
template <int D> bool solve_file(const std::string& file, const Arguments& args)
{
  contact::FclibFile<D> stored;
  try
  {
    stored = read_problem<D>(file);
  }
  catch (const contact::FclibError& e)
  {
    std::cerr << "softpack-fclib: " << e.what() << "\n";
    return false;
  }
  const std::string name = std::filesystem::path(file).stem().string();
  const contact::FrictionContactProblem<D>& problem = stored.problem;
  if (args.describe)
  {
    describe(name, problem);
    return true;
  }
  std::vector<double> r(D * problem.num_contacts(), 0.0), u(r.size());
  if (args.from_guess and stored.guess_r)
    r = *stored.guess_r;
  const auto start = std::chrono::steady_clock::now();
  contact::CondensedResult condensed;
  if (args.condense)
    condensed = contact::FrictionlessCondensation<D>(problem).solve(
        problem, r, u, args.options);
  else
    condensed.nlgs = contact::solve_nlgs(problem, r, u, args.options);
  const contact::NlgsResult& result = condensed.nlgs;
  const std::chrono::duration<double> elapsed =
      std::chrono::steady_clock::now() - start;

  if (!args.solution_out.empty())
  {
    std::filesystem::create_directories(args.solution_out);
    write_reactions(
        std::filesystem::path(args.solution_out) / (name + ".r.csv"), r);
  }
  nlohmann::ordered_json line;
  line["problem"] = name;
  line["contacts"] = problem.num_contacts();
  line["iterations"] = result.iterations;
  line["error"] = result.error;
  if (contact::extrapolates<D>(args.options))
    line["extrapolations"] = result.extrapolations;
  if (args.condense)
  {
    line["condensed"] = condensed.condensed;
    line["held"] = condensed.held;
    line["held_terms"] = condensed.held_terms;
    line["rounds"] = condensed.rounds;
    line["swept_whole"] = condensed.swept_whole;
  }
  line["seconds"] = elapsed.count();
  line["converged"] = result.converged;
  std::cout << line.dump() << std::endl;
  if (!result.converged)
  {
    std::cerr << "softpack-fclib: " << file << ": not converged, error "
              << result.error << " > tolerance " << args.options.tolerance
              << " after " << result.iterations << " sweeps\n";
  }
  return result.converged;
}
/// The command line's options into `args` (and the sweep order's name)
void add_options(CLI::App& app, Arguments& args, std::string& order)
{
  app.add_option("files", args.files,
                 "FCLIB HDF5 files (2D: /fclib_local; 3D: /fclib_local or "
                 "/fclib_global) or Siconos text files (NAME.dat)")
      ->required();
  app.add_option("--dim", args.dim, "the problems' dimension")
      ->capture_default_str()
      ->check(CLI::IsMember({2, 3}));
  app.add_option("--tol", args.options.tolerance,
                 "tolerance on the relative natural-map error")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  app.add_option("--max-iter", args.options.max_sweeps,
                 "maximum number of NLGS sweeps")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  app.add_option("--relaxation", args.options.relaxation,
                 "relaxation factor in (0, 2)")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 2.0));
  app.add_option("--order", order,
                 "sweep order: contact (ascending) or alternate (even "
                 "positions, then odd)")
      ->capture_default_str();
  app.add_option("--q-zero", args.options.q_zero_tolerance,
                 "|q|_inf at or below this means q = 0: the answer is r = 0 "
                 "and the error printed is absolute")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  app.add_option("--full-error-every", args.options.full_error_interval,
                 "also compute the full error every this many sweeps (0: "
                 "only when the cheap error passes)")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  app.add_flag_callback(
      "--extrapolate",
      [&args] { args.options.extrapolation = contact::NlgsExtrapolation::on; },
      "follow a constant drift of the sweeps to where a cone stops it "
      "(NlgsExtrapolation)");
  app.add_flag("--condense", args.condense,
               "hold the frictionless contacts' small sets exactly and sweep "
               "the rest (FrictionlessCondensation)");
  app.add_flag("--describe", args.describe,
               "print each problem's structure instead of solving it: "
               "W's off-diagonal blocks by strength (|W_ab| / "
               "sqrt(|W_aa| |W_bb|) at or above 1e-9 ... 1e-2) and the "
               "frictionless contacts' sets W couples, with the extreme "
               "eigenvalues of their diagonally scaled normal blocks");
  app.add_flag("--from-guess", args.from_guess,
               "start from the file's /guesses/1/r when it has one (a "
               "simulation's unsolved problems store their start there)");
  app.add_option("--solution-out", args.solution_out,
                 "write DIR/NAME.r.csv, the reactions one per line");
}
} // namespace

//-----------------------------------------------------------------------------
int main(int argc, char** argv)
{
  CLI::App app{"Solve 2D or 3D frictional contact problems (FCLIB HDF5, "
               "Siconos .dat) with softpack's NLGS"};
  Arguments args;
  std::string order = "contact";
  add_options(app, args, order);
  CLI11_PARSE(app, argc, argv);
  try
  {
    args.options.order = contact::sweep_order(order);
  }
  catch (const std::invalid_argument& e)
  {
    std::cerr << "softpack-fclib: --order: " << e.what() << "\n";
    return 2;
  }

  bool all_ok = true;
  for (const std::string& file : args.files)
  {
    try
    {
      const bool ok =
          args.dim == 3 ? solve_file<3>(file, args) : solve_file<2>(file, args);
      all_ok = ok and all_ok;
    }
    catch (const std::exception& e)
    {
      std::cerr << "softpack-fclib: " << file << ": " << e.what() << "\n";
      all_ok = false;
    }
  }
  return all_ok ? 0 : 1;
}
