// The sweep order (NlgsOptions::order) and the scheduled full error
// (NlgsOptions::full_error_interval): the same answers, fewer sweeps. The
// same bits on one thread and on two: test_sweep_split.cpp.

#include "error.h"
#include "fclib_io.h"
#include "helpers.h"
#include "nlgs.h"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

using namespace softpack::contact;
using namespace softpack::contact::test;

namespace
{
/// n contacts in a row coupled as exp(-distance / decay) (a positive
/// definite kernel): neighbours coupled almost as strongly as each with
/// itself. All closed and sticking at the answer r*. (On this problem the
/// alternate order needs more sweeps than the contact order; its gain is
/// measured on the simulator's own problems, docs/performance.md.)
struct Interface
{
  FrictionContactProblem2D problem;
  Eigen::VectorXd answer;
};

Interface interface(int n, double decay)
{
  Eigen::MatrixXd W = Eigen::MatrixXd::Zero(2 * n, 2 * n);
  Eigen::VectorXd r(2 * n);
  for (int a = 0; a < n; ++a)
  {
    for (int b = 0; b < n; ++b)
    {
      const double g = std::exp(-std::abs(a - b) / decay);
      W(2 * a, 2 * b) = g;
      W(2 * a + 1, 2 * b + 1) = 0.6 * g;
    }
    r[2 * a] = 1.0 + 0.3 * std::sin(0.7 * a);
    r[2 * a + 1] = 0.1 * std::cos(1.3 * a) * r[2 * a];
  }
  // u* = 0 (closed, sticking): q = -W r*
  return {make_problem(W, -W * r, std::vector<double>(n, 0.3)), r};
}

NlgsResult solve(const FrictionContactProblem2D& p, NlgsOptions opt,
                 std::vector<double>& r)
{
  r.assign(2 * p.num_contacts(), 0.0);
  std::vector<double> u(r.size());
  return solve_nlgs(p, r, u, opt);
}
} // namespace

TEST(SweepOrder, AlternateReachesTheSameAnswer)
{
  const Interface s = interface(40, 3.0);
  NlgsOptions opt;
  opt.tolerance = 1e-8;
  opt.relaxation = 1.7;
  std::vector<double> in_contact_order, alternate;
  const NlgsResult one = solve(s.problem, opt, in_contact_order);
  opt.order = SweepOrder::alternate;
  const NlgsResult two = solve(s.problem, opt, alternate);
  ASSERT_TRUE(one.converged);
  ASSERT_TRUE(two.converged);
  // measured 3.5e-7 and 3.7e-7 off (answers up to 1.3), 2026-12-03
  for (int k = 0; k < s.answer.size(); ++k)
  {
    EXPECT_NEAR(in_contact_order[k], s.answer[k], 4e-6) << k;
    EXPECT_NEAR(alternate[k], s.answer[k], 4e-6) << k;
  }
}

TEST(SweepOrder, EveryFclibProblemIsSolvedToItsErrorInEitherOrder)
{
  for (const DataProblem& d : data_problems())
    for (const SweepOrder order : {SweepOrder::contact, SweepOrder::alternate})
    {
      const FrictionContactProblem2D p = read_fclib_local(hdf5_file(d.name));
      NlgsOptions opt;
      opt.tolerance = d.tolerance;
      opt.max_sweeps = 10000;
      opt.order = order;
      std::vector<double> r;
      const NlgsResult res = solve(p, opt, r);
      EXPECT_TRUE(res.converged) << d.name;
      // The error again, from the returned reactions alone.
      std::vector<double> w(r.size());
      EXPECT_LE(compute_error(p, r, w, opt.q_zero_tolerance).value, d.tolerance)
          << d.name;
    }
}

TEST(SweepOrder, AScheduledFullErrorStopsNoLaterThanTheCheapOne)
{
  // The cheap error of an over-relaxed sweep lags the full error: checking
  // the full error every few sweeps stops at least as early, at an error
  // within the tolerance.
  const Interface s = interface(40, 3.0);
  NlgsOptions opt;
  opt.tolerance = 1e-8;
  opt.relaxation = 1.7;
  std::vector<double> r;
  opt.full_error_interval = 0;
  const NlgsResult cheap_only = solve(s.problem, opt, r);
  opt.full_error_interval = 5;
  const NlgsResult scheduled = solve(s.problem, opt, r);
  ASSERT_TRUE(cheap_only.converged);
  ASSERT_TRUE(scheduled.converged);
  EXPECT_LE(scheduled.error, opt.tolerance);
  EXPECT_LE(scheduled.iterations, cheap_only.iterations);
  std::cout << "[ sweeps   ] cheap error only " << cheap_only.iterations
            << ", full error every 5 sweeps " << scheduled.iterations << "\n";
}

TEST(SweepOrder, AlternateIsTheContactOrderOfTheRenumberedProblem)
{
  // The solver renumbers the problem in its sweep order (so that a sweep
  // reads W's rows one after the other): the same sweeps and the same bits
  // as sweeping the caller's numbering in that order, which is what
  // renumbering the problem by hand and sweeping it in the contact order
  // does. (Only the full error sums its terms in another order: it may
  // differ in its last bits.)
  for (const DataProblem& d : data_problems())
  {
    const FrictionContactProblem2D p = read_fclib_local(hdf5_file(d.name));
    const std::size_t n = p.num_contacts();
    std::vector<std::int32_t> order;
    for (std::size_t first : {0, 1})
      for (std::size_t a = first; a < n; a += 2)
        order.push_back(static_cast<std::int32_t>(a));
    FrictionContactProblem2D by_hand;
    by_hand.W = p.W.renumbered(order);
    for (const std::int32_t a : order)
    {
      by_hand.q.insert(by_hand.q.end(), {p.q[2 * a], p.q[2 * a + 1]});
      by_hand.friction.push_back(p.friction[a]);
    }
    NlgsOptions opt;
    opt.tolerance = d.tolerance;
    opt.relaxation = 1.3;
    opt.full_error_interval = 0; // stop on the cheap error, summed alike
    std::vector<double> r_hand, r;
    const NlgsResult hand = solve(by_hand, opt, r_hand);
    opt.order = SweepOrder::alternate;
    const NlgsResult solver = solve(p, opt, r);
    EXPECT_EQ(solver.iterations, hand.iterations) << d.name;
    EXPECT_NEAR(solver.error, hand.error, 1e-12 * hand.error + 1e-300)
        << d.name;
    for (std::size_t i = 0; i < n; ++i)
    {
      EXPECT_EQ(r[2 * order[i]], r_hand[2 * i]) << d.name << " " << i;
      EXPECT_EQ(r[2 * order[i] + 1], r_hand[2 * i + 1]) << d.name << " " << i;
    }
  }
}

TEST(SweepOrder, APlanMadeOnceServesEverySolveWithItsW)
{
  // The driver makes a SweepPlan once per W and solves each Newton
  // iteration's q with it: the same bits as a solve that makes its own.
  DataProblem d; // the largest of the data problems
  FrictionContactProblem2D p;
  for (const DataProblem& each : data_problems())
  {
    FrictionContactProblem2D candidate = read_fclib_local(hdf5_file(each.name));
    if (candidate.num_contacts() > p.num_contacts())
    {
      d = each;
      p = std::move(candidate);
    }
  }
  NlgsOptions opt;
  opt.tolerance = d.tolerance;
  opt.relaxation = 1.3;
  opt.order = SweepOrder::alternate;
  opt.split_min_contacts = 3;
  ASSERT_TRUE(splits(p, opt));
  SweepPlan plan(p, opt);
  for (const double scale : {1.0, 0.5, 2.0})
  {
    FrictionContactProblem2D scaled = p;
    for (double& q : scaled.q)
      q *= scale;
    std::vector<double> r_own(2 * p.num_contacts()), r_plan(r_own.size()),
        u_own(r_own.size()), u_plan(r_own.size());
    const NlgsResult own = solve_nlgs(scaled, r_own, u_own, opt);
    const NlgsResult planned =
        solve_nlgs(scaled, r_plan, u_plan, opt, nullptr, &plan);
    EXPECT_TRUE(planned.converged) << scale;
    EXPECT_EQ(planned.iterations, own.iterations) << scale;
    EXPECT_EQ(planned.error, own.error) << scale;
    EXPECT_EQ(r_plan, r_own) << scale;
    EXPECT_EQ(u_plan, u_own) << scale;
  }
  // A plan for other options or another problem is refused.
  std::vector<double> r(2 * p.num_contacts()), u(r.size());
  NlgsOptions other = opt;
  other.order = SweepOrder::contact;
  EXPECT_THROW(solve_nlgs(p, r, u, other, nullptr, &plan),
               std::invalid_argument);
  FrictionContactProblem2D q = p; // one contact fewer
  q.friction.pop_back();
  q.q.resize(q.q.size() - 2);
  q.W = DelassusMatrix(q.num_contacts());
  for (std::size_t a = 0; a < q.num_contacts(); ++a)
    q.W.add_block(a, a, p.W.diagonal(a));
  q.W.finalize();
  std::vector<double> rq(2 * q.num_contacts()), uq(rq.size());
  EXPECT_THROW(solve_nlgs(q, rq, uq, opt, nullptr, &plan),
               std::invalid_argument);
}
