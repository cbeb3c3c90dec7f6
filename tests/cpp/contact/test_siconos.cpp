// Agreement with Siconos numerics' own 2D NSGS (Debian
// libsiconos-numerics-dev), run here on the .dat originals of the set.

#include "error.h"
#include "fclib_io.h"
#include "helpers.h"
#include "nlgs.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>

#ifdef SOFTPACK_HAVE_SICONOS
#include "siconos_reference.h"
#endif

using namespace softpack::contact;
using namespace softpack::contact::test;

namespace
{
/// The local problems of the set (the gfc2d .dat is a global problem).
std::vector<DataProblem> local_problems()
{
  std::vector<DataProblem> all = data_problems();
  std::erase_if(all, [](const DataProblem& d)
                { return d.name.rfind("gfc2d", 0) == 0; });
  return all;
}

double distance(const std::vector<double>& a, const std::vector<double>& b)
{
  double d = 0;
  for (std::size_t k = 0; k < a.size(); ++k)
    d += (a[k] - b[k]) * (a[k] - b[k]);
  return std::sqrt(d);
}

double norm(const std::vector<double>& a)
{
  return distance(a, std::vector<double>(a.size(), 0.0));
}
} // namespace

class SiconosAgreement : public ::testing::TestWithParam<DataProblem>
{
};

#ifdef SOFTPACK_HAVE_SICONOS

TEST_P(SiconosAgreement, SameReactionsAndSameError)
{
  const DataProblem& d = GetParam();
  const std::string dat =
      (data_dir() / "siconos_dat" / (d.name + ".dat")).string();
  const FrictionContactProblem2D p = read_fclib_local(hdf5_file(d.name));
  const int n = static_cast<int>(2 * p.num_contacts());

  std::vector<double> r_sic(n), u_sic(n);
  SiconosFc2dResult sic{};
  ASSERT_EQ(siconos_fc2d_nsgs(dat.c_str(), d.tolerance, 10000, r_sic.data(),
                              u_sic.data(), n, &sic),
            0);
  ASSERT_EQ(sic.contacts, static_cast<int>(p.num_contacts()));

  NlgsOptions opt;
  opt.tolerance = d.tolerance;
  std::vector<double> r(n, 0.0), u(n);
  const NlgsResult ours = solve_nlgs(p, r, u, opt);
  ASSERT_TRUE(ours.converged);

  std::vector<double> u_check(n);
  const NaturalMapError sic_mine = compute_error(p, r_sic, u_check, 0.0);
  if (ours.q_zero)
  {
    // q is rounding noise: ours answers r = 0 by design; Siconos solves the
    // noise, so its reactions and velocities must be of the noise's size
    const double q_max = *std::max_element(
        p.q.begin(), p.q.end(),
        [](double a, double b) { return std::abs(a) < std::abs(b); });
    std::cout << "[ siconos  ] " << d.name << ": q = 0 within "
              << std::abs(q_max)
              << "; ours r = 0, siconos |r| = " << norm(r_sic)
              << ", |u| = " << norm(u_check) << "\n";
    EXPECT_EQ(norm(r), 0.0);
    EXPECT_LE(norm(u_check), 10 * std::sqrt(double(n)) * opt.q_zero_tolerance);
    EXPECT_LE(sic.error, d.tolerance);
    return;
  }
  const double rel = distance(r, r_sic) / std::max(norm(r_sic), norm(r));
  std::cout << "[ siconos  ] " << d.name << ": sweeps ours " << ours.iterations
            << " siconos " << sic.iterations << " (info " << sic.info
            << "), error ours " << ours.error << " siconos " << sic.error
            << ", |r - r_siconos|/|r| = " << rel << "\n";
  RecordProperty("relative_distance", std::to_string(rel));
  // Both at a natural-map error <= tol on the same problem: the reactions
  // agree to well within what that error allows
  EXPECT_LE(rel, 1e-6);
  EXPECT_LE(sic.error, d.tolerance);

  // Our error is Siconos' fc2d_compute_error, up to rounding in W r + q
  double sic_error_of_ours = -1;
  ASSERT_EQ(siconos_fc2d_error(dat.c_str(), r.data(), n, &sic_error_of_ours),
            0);
  EXPECT_NEAR(ours.error, sic_error_of_ours, 1e-6 * sic_error_of_ours + 1e-14);
  EXPECT_NEAR(sic_mine.value, sic.error, 1e-6 * sic.error + 1e-14);
}

#else

TEST_P(SiconosAgreement, SameReactionsAndSameError)
{
  GTEST_FAIL() << "Siconos numerics (libsiconos-numerics-dev) was not found "
                  "when configuring: the comparison did not run";
}

#endif

INSTANTIATE_TEST_SUITE_P(Data, SiconosAgreement,
                         ::testing::ValuesIn(local_problems()),
                         [](const auto& info) { return info.param.name; });
