#pragma once

#include <Eigen/Core>
#include <array>
#include <bodies/BodySet.h>
#include <detection/detection.h>
#include <span>
#include <vector>

namespace softpack::dynamics
{

/// One node's share in a contact: the columns of H for this contact are
/// weight * n and weight * t at the node's two DOFs.
struct NodeTerm
{
  int body;
  std::int32_t node; ///< local node of `body`
  double weight;     ///< +1 candidate, -(1 - xi) and -xi antagonist
};

/// The contact operator H of a set of contacts (METHOD.md §3): relative
/// velocities \f$U = H^T v - U_{wall}\f$ and nodal impulses \f$H R\f$.
class ContactOperator
{
public:
  /// @param[in] contacts Contacts (frames fixed for the time step)
  /// @param[in] walls Walls (their velocities enter U)
  /// @param[in] cell A periodic cell (nullptr: none): an image contact's
  /// antagonist moves with the cell's rate at its shift, L h k, which enters
  /// U as a wall's velocity does (docs/periodic_cell.md)
  ContactOperator(const std::vector<Contact>& contacts,
                  const std::vector<Wall>& walls,
                  const PeriodicCell* cell = nullptr);

  /// Number of contacts
  std::size_t size() const { return _frames.size(); }

  /// Node terms of contact a (1 for a wall contact, 3 for node-to-segment)
  std::span<const NodeTerm> terms(std::size_t a) const
  {
    return {_terms.data() + _offsets[a], _terms.data() + _offsets[a + 1]};
  }

  /// Frame (n, t) of contact a as the columns of a 2x2 matrix
  const Eigen::Matrix2d& frame(std::size_t a) const { return _frames[a]; }

  /// Local velocity of the wall, (n, t), or of the antagonist's image
  /// relative to its body (a periodic cell); zero otherwise
  const Eigen::Vector2d& wall_velocity(std::size_t a) const
  {
    return _wall_velocity[a];
  }

  /// Set contact a's wall velocity (a servo wall's changes within a step:
  /// its free velocity for the contact solves, its mid-step one for the
  /// energy accounts).
  /// @param[in] a Contact index (a wall contact)
  /// @param[in] velocity The wall's velocity (global x, y)
  void set_wall_velocity(std::size_t a, const std::array<double, 2>& velocity)
  {
    _wall_velocity[a] =
        _frames[a].transpose() * Eigen::Vector2d(velocity[0], velocity[1]);
  }

  /// \f$U = H^T v - U_{wall}\f$, 2 per contact (n, t)
  /// @param[in] bodies Bodies (node maps)
  /// @param[in] v Global velocity vector
  std::vector<double> relative_velocity(const bodies::BodySet& bodies,
                                        std::span<const double> v) const;

  /// Add \f$H R\f$ to per-body force vectors (local numbering).
  /// @param[in] R Impulses, 2 per contact (n, t)
  /// @param[in,out] per_body One vector per body, sized to its DOFs, or
  /// empty: that body's terms are skipped (a rank of a distributed run
  /// needs its own bodies' and the rigid ones' only)
  void add_impulses(std::span<const double> R,
                    std::vector<Eigen::VectorXd>& per_body) const;

private:
  std::vector<NodeTerm> _terms;
  std::vector<std::int32_t> _offsets;
  std::vector<Eigen::Matrix2d> _frames;
  std::vector<Eigen::Vector2d> _wall_velocity;
};

} // namespace softpack::dynamics
