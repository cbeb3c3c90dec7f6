// The domain-wise NLGS over MPI ranks (parallel::ContactDomains): each rank
// holds W's rows of its own contacts only, the interfaces' reactions go
// point to point, the sums through allreduces (run alone and under mpirun
// -np 2 and -np 3 by CTest). The same plans on threads of one process:
// tests/cpp/contact/test_nlgs_domains.cpp.
#include <algorithm>
#include <cmath>
#include <contact/error.h>
#include <contact/fclib_io.h>
#include <contact/nlgs.h>
#include <gtest/gtest.h>
#include <helpers.h>
#include <parallel/communicator.h>
#include <parallel/contact_domains.h>

using namespace softpack;
using namespace softpack::contact;

namespace
{
/// The problem with W's rows of rank `me`'s contacts only (what a rank
/// holds), contact a owned by rank a * size / n.
FrictionContactProblem2D own_rows(const FrictionContactProblem2D& p,
                                  std::vector<int>& owner, int me, int size)
{
  const std::size_t n = p.num_contacts();
  owner.resize(n);
  FrictionContactProblem2D mine = p;
  mine.W = DelassusMatrix(n);
  for (std::size_t a = 0; a < n; ++a)
  {
    owner[a] = static_cast<int>(a * size / n);
    if (owner[a] != me)
      continue;
    mine.W.add_block(a, a, p.W.diagonal(a));
    for (std::size_t k = 0; k < p.W.row_columns(a).size(); ++k)
      mine.W.add_block(a, p.W.row_columns(a)[k], p.W.row_blocks(a)[k]);
  }
  mine.W.finalize();
  return mine;
}

/// Whether every rank holds the same bits in x
bool same_on_every_rank(const parallel::Communicator& comm,
                        const std::vector<double>& x)
{
  std::vector<double> low = x, high = x;
  MPI_Allreduce(MPI_IN_PLACE, low.data(), static_cast<int>(low.size()),
                MPI_DOUBLE, MPI_MIN, comm.comm());
  MPI_Allreduce(MPI_IN_PLACE, high.data(), static_cast<int>(high.size()),
                MPI_DOUBLE, MPI_MAX, comm.comm());
  return low == x && high == x;
}
} // namespace

TEST(ContactDomains, FclibProblemsSolvedToTheirErrorOnEveryRankCount)
{
  const parallel::Communicator comm(MPI_COMM_WORLD);
  for (const contact::test::DataProblem& d : contact::test::data_problems())
  {
    const FrictionContactProblem2D p =
        read_fclib_local(contact::test::hdf5_file(d.name));
    const std::size_t n = p.num_contacts();
    if (n < static_cast<std::size_t>(comm.size()))
      continue;
    NlgsOptions opt;
    opt.tolerance = d.tolerance;
    opt.max_sweeps = 20000;
    std::vector<double> serial_r(2 * n, 0.0), serial_u(2 * n);
    const NlgsResult serial = solve_nlgs(p, serial_r, serial_u, opt);

    std::vector<int> owner;
    const FrictionContactProblem2D mine =
        own_rows(p, owner, comm.rank(), comm.size());
    parallel::ContactTraffic traffic;
    const parallel::ContactDomains domains(comm, mine.W, owner, traffic);
    std::vector<double> r(2 * n, 0.0), u(2 * n, 0.0);
    const NlgsResult result = solve_nlgs(mine, r, u, opt, &domains.domain());

    EXPECT_TRUE(result.converged) << d.name;
    EXPECT_TRUE(same_on_every_rank(comm, r)) << d.name;
    std::vector<double> w(2 * n);
    EXPECT_LE(compute_error(p, r, w, opt.q_zero_tolerance).value, d.tolerance)
        << d.name;
    // u = W r + q at this rank's own contacts (its rows)
    double scale = 0;
    for (const double value : w)
      scale = std::max(scale, std::abs(value));
    for (std::size_t a = 0; a < n; ++a)
      for (int c = 0; c < 2 && owner[a] == comm.rank(); ++c)
        ASSERT_NEAR(u[2 * a + c], w[2 * a + c], 1e-12 * scale + 1e-300)
            << d.name << " contact " << a;
    EXPECT_EQ(traffic.sweeps, 0u); // counted by the caller, not here
    if (comm.size() == 1)
    {
      // One domain, every contact interior, in contact order: the serial
      // sweep, bit for bit, with no message.
      EXPECT_EQ(r, serial_r) << d.name;
      EXPECT_EQ(result.iterations, serial.iterations) << d.name;
    }
    else
    {
      // The serial sweep in another order (interiors, then interfaces
      // colour by colour): about its sweep count (thread domains: equal or
      // up to 0.6 % more).
      EXPECT_LE(result.iterations, 1.05 * serial.iterations + 2) << d.name;
      // Each sweep: one allreduce of its sums at least
      EXPECT_GE(traffic.messages, static_cast<std::size_t>(result.iterations))
          << d.name;
    }
  }
}
