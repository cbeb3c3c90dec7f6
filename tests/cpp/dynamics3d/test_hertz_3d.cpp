// A sphere (D 20 mm, neo-Hookean, mu 0.15 MPa, 3D lambda = 2 mu) squeezed
// between two frictionless plane walls through the 3D step, against the
// axisymmetric dolfinx reference (softpack.references.sphere_axisym) and
// Hertz's law for a sphere on a rigid flat (K. L. Johnson, Contact Mechanics,
// 1985, eq. 4.22-4.23): F = (4/3) E* sqrt(R) delta^(3/2) at each plate, delta
// the approach at each plate (half the plates' closure), E* = E / (1 - nu^2),
// E = mu (3 lambda + 2 mu) / (lambda + mu), nu = lambda / (2 (lambda + mu)).
// The plates move in small increments and hold; theta = 1 and steps of
// 1 ms (the inertia M / h^2 is a few per cent of the stiffness: each hold is
// a static solve to the Newton tolerance).
#include "../dynamics/scheme_options.h"
#include "sphere_scenes.h"
#include <cmath>
#include <cstdlib>
#include <gtest/gtest.h>
#include <sstream>

using namespace softpack;

namespace
{
struct HertzPoint
{
  double eps, force, hertz;
  double error() const { return force / hertz - 1; }
};

double hertz_force(double delta)
{
  const double mu = test::sphere_mu, lambda = test::sphere_lambda;
  const double E = mu * (3 * lambda + 2 * mu) / (lambda + mu);
  const double nu = lambda / (2 * (lambda + mu));
  const double E_star = E / (1 - nu * nu);
  return 4.0 / 3.0 * E_star * std::sqrt(test::sphere_radius) *
         std::pow(delta, 1.5);
}

/// The walls of a squeeze: two plates at the poles of a whole sphere, or
/// for its octant x, y, z >= 0 the symmetry planes x = 0, y = 0 and the
/// equator z = 0 (fixed, frictionless) and the plate at its pole
std::vector<dynamics::Wall3D> squeeze_walls(bool octant, double bottom,
                                            double top)
{
  if (!octant)
    return {{"bottom", {0, 0, bottom}, {0, 0, 1}, {0, 0, 0}},
            {"top", {0, 0, top}, {0, 0, -1}, {0, 0, 0}}};
  // The symmetry planes hold the nodes on them both ways (tension up to
  // 10 N per node: a few hundred times the largest reaction here)
  const double bilateral = 10;
  return {{"x0", {0, 0, 0}, {1, 0, 0}, {0, 0, 0}, bilateral},
          {"y0", {0, 0, 0}, {0, 1, 0}, {0, 0, 0}, bilateral},
          {"bottom", {0, 0, 0}, {0, 0, 1}, {0, 0, 0}, bilateral},
          {"top", {0, 0, top}, {0, 0, -1}, {0, 0, 0}}};
}

/// The squeeze's step: theta = 1, steps of h, frictionless, tight tolerances
dynamics::MoreauJeanOptions squeeze_options(double h)
{
  dynamics::MoreauJeanOptions o = test::exact_options(h, 1e-3);
  o.time.theta = 1;
  o.time.newton_tolerance = 1e-8;
  o.time.newton_max_iterations = 50;
  // The tangent kept while Newton converges fast (strains are small): the
  // compliance columns of the contact nodes are then made once per
  // refactorization, not per iteration
  o.time.full_newton = false;
  o.time.tangent_reuse_steps = 50;
  o.time.refactor_above_iterations = 8;
  o.contact.friction = 0;
  // (the plates move by 2e-5 m per step at most)
  o.contact.alert_distance = 1e-4;
  o.contact.nlgs_tolerance = 1e-10;
  return o;
}

/// The plates' force at the strains `eps` (closure / D), each reached in
/// `increments` steps and held for `hold` steps. `octant`: the body is the
/// octant x, y, z >= 0 of the sphere (sphere_meshes.py octant), its plate
/// moving by half the whole sphere's closure; the force is 4 x its own.
std::vector<HertzPoint> squeeze(bodies::BodySet bodies,
                                const std::vector<double>& eps,
                                bool octant = false, int increments = 5,
                                int hold = 4)
{
  const std::span<const double> X = bodies.reference_coordinates();
  double top = -1, bottom = 1;
  for (std::size_t n = 0; n < X.size() / 3; ++n)
  {
    top = std::max(top, X[3 * n + 2]);
    bottom = std::min(bottom, X[3 * n + 2]);
  }
  const double h = 1e-3, D = octant ? 2 * top : top - bottom;
  dynamics::MoreauJean scheme(bodies, squeeze_options(h),
                              squeeze_walls(octant, bottom, top));
  const std::size_t plate = octant ? 3 : 1;
  std::vector<HertzPoint> out;
  double closure = 0;
  dynamics::StepTimings seconds;
  int sweeps = 0, contacts = 0;
  auto step = [&]
  {
    const dynamics::StepReport r = scheme.step();
    EXPECT_TRUE(r.newton_converged);
    EXPECT_TRUE(r.nlgs_converged);
    seconds += r.seconds;
    sweeps += r.nlgs_iterations;
    contacts = r.contacts;
  };
  for (const double e : eps)
  {
    const double speed = (e * D - closure) / 2 / (increments * h);
    if (!octant)
      scheme.walls_3d()[0].velocity[2] = speed;
    scheme.walls_3d()[plate].velocity[2] = -speed;
    for (int s = 0; s < increments; ++s)
      step();
    scheme.walls_3d()[0].velocity[2] = 0;
    scheme.walls_3d()[plate].velocity[2] = 0;
    double force[2] = {0, 0};
    for (int s = 0; s < hold; ++s)
    {
      step();
      const auto& f = scheme.wall_forces_3d();
      force[0] = force[1];
      force[1] = octant ? -4 * f[plate][2] : 0.5 * (f[0][2] - f[plate][2]);
    }
    // At rest: the last two holds agree, the plates' forces balance
    EXPECT_NEAR(force[1], force[0], 1e-3 * std::abs(force[1]));
    closure = octant ? 2 * (top - scheme.walls_3d()[plate].point[2])
                     : scheme.walls_3d()[0].point[2] - bottom +
                           (top - scheme.walls_3d()[plate].point[2]);
    out.push_back({closure / D, -force[1], hertz_force(closure / 2)});
  }
  std::cout << "  (" << contacts << " contacts at the end, " << sweeps
            << " NLGS sweeps; seconds: factorization " << seconds.factorization
            << ", Delassus " << seconds.delassus << ", NLGS " << seconds.nlgs
            << ", total " << seconds.total() << ")\n";
  return out;
}

std::string table(const std::string& mesh, const bodies::BodySet& bodies,
                  const std::vector<HertzPoint>& points)
{
  std::ostringstream s;
  s << mesh << " (" << bodies.num_global_dofs() / 3 << " nodes):";
  for (const HertzPoint& p : points)
    s << " eps " << p.eps << ": F " << p.force << " N, Hertz " << p.hertz
      << " N, error " << 100 * p.error() << " %;";
  return s.str();
}
} // namespace

TEST(Hertz3D, CoarseSphereBetweenFrictionlessPlatesFollowsHertz)
{
  // The CI mesh (476 nodes, 0.8 mm at the poles, 4 mm inside): linear
  // tetrahedra this coarse make the sphere 27-36 % stiffer than the
  // converged continuum, the axisymmetric reference of
  // `./softpack reference-sphere` (itself 3.1, 4.6, 6.9 % above Hertz at
  // these strains: docs/contact_3d.md, "Hertz: the reference"), 36-41 %
  // than Hertz; the error falls with the mesh ("Hertz: the mesh study"),
  // which bounds the amplitude here. The exponent 3/2 holds on this mesh
  // already between eps = 0.01 and 0.02.
  const std::vector<HertzPoint> p =
      squeeze(test::spheres("hertz"), {0.005, 0.01, 0.02});
  std::cout << table("hertz", test::spheres("hertz"), p) << "\n";
  // The reference's forces (N; h = 0.025 mm, penalty 1e6 mu/R)
  const double reference[3] = {0.021877, 0.062775, 0.18134};
  for (std::size_t k = 0; k < p.size(); ++k)
  {
    const HertzPoint& q = p[k];
    EXPECT_GT(q.error(), 0) << "eps " << q.eps; // P1: stiffer, never softer
    EXPECT_LT(q.error(), 0.45) << "eps " << q.eps;
    EXPECT_GT(q.force / reference[k] - 1, 0) << "eps " << q.eps;
    EXPECT_LT(q.force / reference[k] - 1, 0.40) << "eps " << q.eps;
  }
  const double exponent =
      std::log(p[2].force / p[1].force) / std::log(p[2].eps / p[1].eps);
  EXPECT_NEAR(exponent, 1.5, 0.02);
}

TEST(Hertz3D, OctantWithSymmetryWallsIsTheWholeSphere)
{
  // The octant x, y, z >= 0 (103 nodes) between its symmetry planes, held
  // both ways (Wall3D::tensile_strength), and the whole sphere made of its
  // eight mirror images (563 nodes) between two plates: the same elements,
  // the same continuum problem, so the same force up to the solvers'
  // tolerances (measured: equal to 6 digits)
  const std::vector<HertzPoint> octant =
      squeeze(test::spheres("hertz_octant"), {0.005, 0.02}, true);
  const std::vector<HertzPoint> whole =
      squeeze(test::spheres("hertz_mirrored"), {0.005, 0.02});
  std::cout << table("hertz_octant", test::spheres("hertz_octant"), octant)
            << "\n";
  for (std::size_t k = 0; k < whole.size(); ++k)
  {
    EXPECT_NEAR(octant[k].eps, whole[k].eps, 1e-12);
    EXPECT_NEAR(octant[k].force, whole[k].force, 1e-5 * whole[k].force);
  }
}

// The mesh study of docs/contact_3d.md: the meshes of SOFTPACK_HERTZ_MESHES
// (a directory) named in SOFTPACK_HERTZ_NAMES (whole spheres) and
// SOFTPACK_HERTZ_OCTANTS (octants), comma separated.
TEST(Hertz3D, DISABLED_MeshStudy)
{
  const char* dir = std::getenv("SOFTPACK_HERTZ_MESHES");
  const char* names[2] = {std::getenv("SOFTPACK_HERTZ_NAMES"),
                          std::getenv("SOFTPACK_HERTZ_OCTANTS")};
  ASSERT_TRUE(dir && (names[0] || names[1]))
      << "set SOFTPACK_HERTZ_MESHES and _NAMES or _OCTANTS";
  for (int octant = 0; octant < 2; ++octant)
  {
    std::stringstream list(names[octant] ? names[octant] : "");
    for (std::string name; std::getline(list, name, ',');)
    {
      const std::map<std::string, double> param = {
          {"shear_modulus", test::sphere_mu},
          {"lame_lambda", test::sphere_lambda}};
      auto make = [&]
      {
        return bodies::BodySet(
            bodies::read_body_mesh(MPI_COMM_SELF, std::filesystem::path(dir) /
                                                      (name + ".xdmf")),
            forms::find_material("neo_hookean"), param, test::sphere_rho);
      };
      std::cout << table(name, make(),
                         squeeze(make(), {0.005, 0.01, 0.02}, octant == 1))
                << std::endl;
    }
  }
}
