#pragma once

#include "BodySet.h"
#include "nodal_volumetric.h"
#include <dolfinx/fem/Form.h>
#include <dolfinx/fem/Function.h>
#include <functional>
#include <map>
#include <material_registry.h>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace softpack::bodies
{

/// The most internal variables per cell a law may have
constexpr int max_internal = 16;

/// One cell integral of a form, callable without the form: the FFCx
/// kernel and the form's constants, packed (a material's constants are
/// fixed for a run).
struct CellKernel
{
  std::function<void(double*, const double*, const double*, const double*,
                     const int*, const std::uint8_t*)>
      tabulate;
  std::vector<double> constants;
  /// How many internal variables of the cell the kernel reads after its
  /// displacement (0: none; a law with internal variables, BodySet)
  int internal = 0;
};

/// The kernels of a law with internal variables (forms::MaterialForms::
/// internal_update), taken from its compiled forms (internal_forms): its
/// forms read a DG0 coefficient beside the displacement, which the body
/// assembly passes cell by cell.
struct InternalForms
{
  CellKernel energy, residual, tangent, update;
  /// The entry of update.constants that is the step size
  std::size_t time_step = 0;
};

/// The forms of one material that run body by body: the strain energy,
/// the internal force, the tangent and the two masses.
struct BodyForms
{
  const dolfinx::fem::Form<double>* energy;
  const dolfinx::fem::Form<double>* residual;
  const dolfinx::fem::Form<double>* tangent;
  const dolfinx::fem::Form<double>* mass;
  const dolfinx::fem::Form<double>* lumped_mass;
  /// A law with internal variables: its kernels (energy, residual and
  /// tangent then null)
  std::optional<InternalForms> internal = std::nullopt;
  /// A law with its volumetric energy at the nodes: its lambda (0: none;
  /// nodal_volumetric.h)
  double nodal_lambda = 0;
};

/// The kernels of a law with internal variables, their constants the
/// material's (the step size's entry 0 until set)
/// @throws std::invalid_argument naming the law and form of another kind
/// (one cell integral, coefficients u then internal)
InternalForms internal_forms(const forms::MaterialForms& law,
                             const std::map<std::string, double>& constants);

/// Call `kernel` on each cell of `body` (of dimension D: body.dim), in
/// order, with the cell's node coordinates (x, global interleaved; z = 0 in
/// 2D) and displacement (u, global interleaved; none when empty), and hand
/// (k, element tensor of N values) to add, k the cell's index in
/// body.cell_nodes and body.cells. A kernel that reads internal variables
/// gets cell c's from internal[stride c].
template <int N, int D = 2, typename Add>
void for_each_cell(const Body& body, const CellKernel& kernel,
                   std::span<const double> x, std::span<const double> u,
                   Add&& add, std::span<const double> internal = {},
                   int stride = 0)
{
  constexpr int nodes = D + 1, dofs = D * nodes;
  // In 2D z stays 0: the geometry's third component
  double coordinates[3 * nodes] = {};
  double w[dofs + max_internal] = {}, tensor[N];
  for (std::size_t k = 0; k < body.cell_nodes.size(); ++k)
  {
    const CellNodes& cell = body.cell_nodes[k];
    for (int i = 0; i < nodes; ++i)
    {
      const std::int32_t g = body.nodes[cell[i]];
      for (int c = 0; c < D; ++c)
      {
        coordinates[3 * i + c] = x[D * g + c];
        if (!u.empty())
          w[D * i + c] = u[D * g + c];
      }
    }
    for (int i = 0; i < kernel.internal; ++i)
      w[dofs + i] = internal[std::size_t(stride) * body.cells[k] + i];
    std::fill_n(tensor, N, 0.0);
    kernel.tabulate(tensor, w, kernel.constants.data(), coordinates, nullptr,
                    nullptr);
    add(k, static_cast<const double*>(tensor));
  }
}

/// Assembly of the per-body forms body by body, on all cores.
///
/// dolfinx's assemblers run on one core, over the cells of the whole mesh,
/// and pack every coefficient into a separate array first; these loops call
/// the same FFCx kernels cell by cell, read the node coordinates and the
/// displacement straight from their global arrays through each body's
/// cells (Body::cell_nodes), and give whole bodies to the threads (bodies
/// share no node, so no two threads write the same entry). Each entry sums
/// its cells' contributions in the order dolfinx's assemblers do (a body's
/// cells in increasing order). The coordinates are the BodySet's reference
/// coordinates (tabulated for the DOFs, what detection, areas and the
/// state file read), which differ from the mesh geometry dolfinx's
/// assemblers read by rounding: the results agree with theirs to ~1e-14
/// of the largest entry (tests/cpp/bodies/test_body_assembly.cpp). The
/// kernels need nothing of the mesh after construction: a body is
/// assembled from its cells and coordinates alone.
///
/// The forms must be of the kind the materials produce (P1 vectors on
/// triangles or tetrahedra, one cell integral, the displacement as the
/// only coefficient or none, no DOF transformations); anything else is
/// refused. The dimension is the forms' (that of the displacement's mesh):
/// each loop runs its cells with the dimension a template parameter
/// (for_each_cell), so 2D and 3D bodies share every line. Built, the
/// assembly holds no dolfinx object: the forms, spaces and mesh may go.
class BodyAssembly
{
public:
  /// @param[in] forms The forms of each material in use
  /// @param[in] body_forms Index in `forms` of each body's material
  /// @param[in] u The displacement, the only coefficient of the forms
  /// @throws std::invalid_argument naming the form and what it lacks, for
  /// a form of another kind
  BodyAssembly(const std::vector<BodyForms>& forms, std::vector<int> body_forms,
               const std::shared_ptr<const dolfinx::fem::Function<double>>& u);

  /// The strain energy of each cell of the flagged bodies (the integral of
  /// Psi over it) into per_cell[c], c the cell's index (Body::cells); the
  /// others' entries are left as they are
  void cell_energy(std::span<double> per_cell, const std::vector<Body>& bodies,
                   std::span<const double> x, std::span<const double> u,
                   std::span<const char> only = {}) const;

  /// The internal variables (the laws' that have them; stride per cell)
  /// the energy, residual and tangent read: a view of the caller's, which
  /// must outlive the calls (BodySet's)
  void set_internal(std::span<const double> internal, int stride)
  {
    _internal = internal;
    _stride = stride;
  }
  /// The internal variables of each cell of the flagged bodies whose law
  /// has them, relaxed over a step h at displacement u (the law's
  /// internal_update) in place (`internal`, stride per cell: the view
  /// set_internal gave), with the cell's dissipation (its strain energy
  /// before less after: the update's last entry) into dissipated[c], and (f not
  /// empty) the body's internal force at the relaxed values into f (its entries
  /// overwritten); one pass over the cells (internal_variables.cpp). The
  /// others' entries are left as they are.
  void relax_internal(std::span<double> internal, double h,
                      const std::vector<Body>& bodies,
                      std::span<const double> x, std::span<const double> u,
                      std::span<double> dissipated, std::span<double> f,
                      std::span<const char> only = {}) const;
  /// Whether body k's law has internal variables
  bool has_internal(int k) const
  {
    return _kernels[_body_forms[k]].update.internal > 0;
  }

  /// b += F_int(u) of the flagged bodies (all when `only` is empty)
  /// @param[in] x Reference coordinates (global, interleaved x, y)
  /// @param[in] u Displacement (global, interleaved)
  void residual(std::span<double> b, const std::vector<Body>& bodies,
                std::span<const double> x, std::span<const double> u,
                std::span<const char> only = {}) const;

  /// K(u) of each flagged body into K[b] (its pattern, create_matrices;
  /// the values overwritten)
  void tangent(std::vector<BodyMatrix>& K, const std::vector<Body>& bodies,
               std::span<const double> x, std::span<const double> u,
               std::span<const char> only = {}) const;

  /// The consistent mass of each flagged body into M[b] (its pattern; the
  /// values overwritten)
  void mass(std::vector<BodyMatrix>& M, const std::vector<Body>& bodies,
            std::span<const double> x, std::span<const char> only = {}) const;

  /// The lumped (vertex-quadrature) mass of each flagged body, one per
  /// DOF: the diagonal of the lumped mass form's matrix (the others' are
  /// empty)
  std::vector<Eigen::VectorXd>
  lumped_mass(const std::vector<Body>& bodies, std::span<const double> x,
              std::span<const char> only = {}) const;

private:
  struct Kernels
  {
    CellKernel energy, residual, tangent, mass, lumped_mass;
    /// A law with internal variables: their update (none: internal = 0)
    CellKernel update;
    std::size_t time_step = 0;
    /// The nodal volumetric energy's lambda (0: none)
    double nodal_lambda = 0;
  };
  /// `kernel` on each cell of body k (of dimension D) with the cells'
  /// internal variables
  template <int N, int D = 2, typename Add>
  void cells(int k, const CellKernel& kernel, const std::vector<Body>& bodies,
             std::span<const double> x, std::span<const double> u,
             Add&& add) const
  {
    for_each_cell<N, D>(bodies[k], kernel, x, u, std::forward<Add>(add),
                        _internal, _stride);
  }
  /// One bilinear form (a member of Kernels) of each flagged body into
  /// A[b] (its pattern; the values overwritten)
  void matrices(CellKernel Kernels::*form, std::vector<BodyMatrix>& A,
                const std::vector<Body>& bodies, std::span<const double> x,
                std::span<const double> u, std::span<const char> only) const;
  /// Body k's nodal patches (a law with nodal_lambda), made on first use
  /// by the one thread that assembles the body
  NodalPatches& nodal(int k, const Body& body, std::span<const double> x) const;
  std::vector<Kernels> _kernels;
  std::vector<int> _body_forms;
  /// The forms' spatial dimension (2 or 3)
  int _dim = 2;
  mutable std::vector<std::unique_ptr<NodalPatches>> _nodal;
  std::span<const double> _internal;
  int _stride = 0;
};

} // namespace softpack::bodies
