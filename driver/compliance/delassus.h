#pragma once

#include "contact_operator.h"
#include "effective_stiffness.h"
#include "rigid_bodies.h"
#include <contact/DelassusMatrix.h>

namespace softpack::dynamics
{

/// The compliance a servo wall adds to W: the wall is a rigid body with one
/// DOF along its normal n, so contact c's relative velocity gains
/// -g_c V with g_c = frame_c^T n, and V gains -(1/m) sum_d g_d . R_d: block
/// (c, d) of W gains inverse_mass g_c g_d^T (every pair of the wall's
/// contacts), kept as one rank-one term (contact::DelassusMatrix::RankOne),
/// not as blocks.
template <int D> struct WallCouplingD
{
  std::vector<std::int32_t> contacts;
  std::vector<Eigen::Matrix<double, D, 1>> g;
  double inverse_mass = 0;
};
using WallCoupling = WallCouplingD<2>;

/// One body's contribution to a block of W (in the order build_delassus
/// adds them).
template <int D> struct DelassusBlockD
{
  std::int32_t body, a, b;
  Eigen::Matrix<double, D, D> block;
};
using DelassusBlock = DelassusBlockD<2>;

/// The bodies' contributions to W (build_delassus's body loop), in body
/// order, for the local bodies (BodySet::local_bodies): what a distributed
/// run's share computes from the compliance of its bodies. The arguments
/// are build_delassus's. D: the contacts' dimension (H.dim(); rigid bodies
/// are 2D only).
template <int D = 2>
std::vector<DelassusBlockD<D>>
delassus_blocks(const bodies::BodySet& bodies, const ContactOperator& H,
                const EffectiveStiffness& Kbar, double drop_tolerance,
                const RigidBodies* rigid);

/// W from the bodies' contributions (in body order: the sums are then
/// those of the serial build, bit for bit) and the servo walls' couplings
/// (rank-one terms, whole on every rank).
/// @param[in] rows 1 for the rows (contacts) wanted, the others left empty
/// (a rank of a distributed run keeps the rows of its own contacts); empty:
/// every row. `blocks` may hold only the wanted rows' contributions.
template <int D>
contact::DelassusMatrixD<D> assemble_delassus(
    std::size_t num_contacts, std::span<const DelassusBlockD<D>> blocks,
    std::span<const WallCouplingD<D>> walls, std::span<const char> rows = {});
/// assemble_delassus<2>
contact::DelassusMatrix assemble_delassus(std::size_t num_contacts,
                                          std::span<const DelassusBlock> blocks,
                                          std::span<const WallCoupling> walls,
                                          std::span<const char> rows = {});

/// Build the Delassus operator \f$W = H^T \bar K^{-1} H\f$ body by body.
///
/// Only boundary nodes carry contacts. The columns of each body's
/// compliance \f$G_b = \bar K_b^{-1}\f$ at the boundary nodes that carry
/// contacts are kept by EffectiveStiffness while the factorization is
/// unchanged, so rebuilding W for a new contact set costs small dense
/// products (and a few solves for newly touched nodes): every pair of
/// contacts touching the body receives
/// \f$\sum_{i,j} w_i w_j\, F_a^T G_b(i, j) F_b\f$ (F the contact frames,
/// w the node weights). No global or dense W is formed.
///
/// The compliance of a mass-dominated \f$\bar K\f$ decays with distance
/// over a few element sizes (a length of order \f$h\theta c\f$, c the wave
/// speed): two contacts on opposite sides of a disk do not feel each other
/// within one time step. Blocks smaller than `drop_tolerance` times the
/// geometric mean of the two contacts' diagonal blocks (Frobenius norms)
/// are left out, a pair (a, b) only when both W_ab and W_ba are (so W's
/// pattern is symmetric), which cuts the cost of every NLGS sweep several
/// times.
/// @param[in] bodies Bodies
/// @param[in] H Contact operator of the step
/// @param[in] Kbar Factorized iteration matrices
/// @param[in] drop_tolerance Relative size below which an off-diagonal
/// block is dropped (0: keep all)
/// @param[in] walls The servo walls' couplings (never dropped)
/// @param[in] rigid The rigid bodies, whose compliance is \f$P_i M_r^{-1}
/// P_j^T\f$ (RigidBodies::compliance) in place of the FE one; it does not
/// decay with distance and none of its blocks is dropped (null: none)
/// @return The finalized block-sparse W
contact::DelassusMatrix build_delassus(const bodies::BodySet& bodies,
                                       const ContactOperator& H,
                                       const EffectiveStiffness& Kbar,
                                       double drop_tolerance = 0,
                                       std::span<const WallCoupling> walls = {},
                                       const RigidBodies* rigid = nullptr);

} // namespace softpack::dynamics
