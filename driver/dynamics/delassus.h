#pragma once

#include "contact_operator.h"
#include "effective_stiffness.h"
#include <contact/DelassusMatrix.h>

namespace softpack::dynamics
{

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
/// @param[in] bodies Bodies
/// @param[in] H Contact operator of the step
/// @param[in] Kbar Factorized iteration matrices
/// @return The finalized block-sparse W
contact::DelassusMatrix build_delassus(const bodies::BodySet& bodies,
                                       const ContactOperator& H,
                                       const EffectiveStiffness& Kbar);

} // namespace softpack::dynamics
