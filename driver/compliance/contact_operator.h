#pragma once

#include <Eigen/Core>
#include <array>
#include <bodies/BodySet.h>
#include <detection/detection.h>
#include <detection/detection_3d.h>
#include <span>
#include <vector>

namespace softpack::dynamics
{

/// One node's share in a contact: the columns of H for this contact are
/// weight times the frame's vectors at the node's dim DOFs.
struct NodeTerm
{
  int body;
  std::int32_t node; ///< local node of `body`
  /// +1 candidate; 2D: -(1 - xi) and -xi on the antagonist segment; 3D:
  /// -w_i on the antagonist triangle's node i
  double weight;
};

/// The contact operator H of a set of contacts (METHOD.md §3): relative
/// velocities \f$U = H^T v - U_{wall}\f$ and nodal impulses \f$H R\f$, D
/// per contact in the contact's frame (n, t) in 2D, (n, t1, t2) in 3D. The
/// dimension is the contacts': one operator, its arithmetic templated on D.
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

  /// 3D node-to-face and node-to-wall contacts (detect_contacts_3d):
  /// +[n t1 t2] on the candidate node, -w_i [n t1 t2] on the antagonist
  /// triangle's node i (the weights that are not 0)
  /// @param[in] walls The plane walls (their imposed velocities enter U)
  ContactOperator(const std::vector<Contact3D>& contacts,
                  const std::vector<Wall3D>& walls);

  /// Unknowns per contact: 2 or 3
  int dim() const { return _dim; }

  /// Number of contacts
  std::size_t size() const { return _wall_velocity.size() / _dim; }

  /// Node terms of contact a (1 for a wall contact, 3 for node-to-segment,
  /// 2 to 4 for node-to-face)
  std::span<const NodeTerm> terms(std::size_t a) const
  {
    return {_terms.data() + _offsets[a], _terms.data() + _offsets[a + 1]};
  }

  /// Frame of contact a as the columns of a D x D matrix ((n, t) in 2D)
  template <int D = 2> Eigen::Matrix<double, D, D> frame(std::size_t a) const
  {
    return Eigen::Map<const Eigen::Matrix<double, D, D>>(_frames.data() +
                                                         D * D * a);
  }

  /// Local velocity of the wall, (n, t...), or of the antagonist's image
  /// relative to its body (a periodic cell); zero otherwise
  template <int D = 2>
  Eigen::Matrix<double, D, 1> wall_velocity(std::size_t a) const
  {
    return Eigen::Map<const Eigen::Matrix<double, D, 1>>(_wall_velocity.data() +
                                                         D * a);
  }

  /// Set contact a's wall velocity (a servo wall's changes within a step:
  /// its free velocity for the contact solves, its mid-step one for the
  /// energy accounts).
  /// @param[in] a Contact index (a wall contact)
  /// @param[in] velocity The wall's velocity (global x, y)
  void set_wall_velocity(std::size_t a, const std::array<double, 2>& velocity)
  {
    const Eigen::Vector2d w =
        frame(a).transpose() * Eigen::Vector2d(velocity[0], velocity[1]);
    _wall_velocity[2 * a] = w[0];
    _wall_velocity[2 * a + 1] = w[1];
  }
  /// The same for a 3D contact (global x, y, z)
  void set_wall_velocity(std::size_t a, const std::array<double, 3>& velocity)
  {
    const Eigen::Vector3d w =
        frame<3>(a).transpose() *
        Eigen::Vector3d(velocity[0], velocity[1], velocity[2]);
    for (int i = 0; i < 3; ++i)
      _wall_velocity[3 * a + i] = w[i];
  }

  /// \f$U = H^T v - U_{wall}\f$, D per contact
  /// @param[in] bodies Bodies (node maps)
  /// @param[in] v Global velocity vector (D per node)
  std::vector<double> relative_velocity(const bodies::BodySet& bodies,
                                        std::span<const double> v) const;

  /// Add \f$H R\f$ to per-body force vectors (local numbering).
  /// @param[in] R Impulses, D per contact
  /// @param[in,out] per_body One vector per body, sized to its DOFs, or
  /// empty: that body's terms are skipped (a rank of a distributed run
  /// needs its own bodies' and the rigid ones' only)
  void add_impulses(std::span<const double> R,
                    std::vector<Eigen::VectorXd>& per_body) const;

private:
  template <int D>
  void add_contact(const Eigen::Matrix<double, D, D>& frame,
                   const Eigen::Matrix<double, D, 1>& wall_velocity);
  template <int D>
  std::vector<double> relative_velocity_d(const bodies::BodySet& bodies,
                                          std::span<const double> v) const;
  template <int D>
  void add_impulses_d(std::span<const double> R,
                      std::vector<Eigen::VectorXd>& per_body) const;

  int _dim = 2;
  std::vector<NodeTerm> _terms;
  std::vector<std::int32_t> _offsets{0};
  /// D x D per contact (column-major), D per contact
  std::vector<double> _frames, _wall_velocity;
};

} // namespace softpack::dynamics
