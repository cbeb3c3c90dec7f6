#pragma once
// The 3D step's test scenes: gmsh spheres (D 20 mm) written by
// sphere_meshes.py in the CTest fixture dynamics3d.meshes, a neo-Hookean
// material, and the step's options for them.
#include <bodies/BodySet.h>
#include <dynamics/moreau_jean.h>
#include <filesystem>
#include <map>
#include <material_registry.h>

namespace softpack::test
{
/// The sphere's material: mu 0.15 MPa, the 3D lambda = 2 mu (nu = 1/3: P1
/// tetrahedra do not lock), rho 1180 kg/m^3
constexpr double sphere_mu = 0.15e6, sphere_lambda = 2 * sphere_mu,
                 sphere_rho = 1180, sphere_radius = 0.01;

/// The bodies of a mesh written by sphere_meshes.py
inline bodies::BodySet spheres(const std::string& name)
{
  const std::filesystem::path file =
      std::filesystem::path(SOFTPACK_SPHERE_MESHES) / (name + ".xdmf");
  const std::map<std::string, double> p = {{"shear_modulus", sphere_mu},
                                           {"lame_lambda", sphere_lambda}};
  return bodies::BodySet(bodies::read_body_mesh(MPI_COMM_SELF, file),
                         forms::find_material("neo_hookean"), p, sphere_rho);
}

/// Total momentum sum_b M_b v_b (consistent masses), per direction
inline std::array<double, 3> momentum(const bodies::BodySet& bodies,
                                      std::span<const double> v)
{
  std::array<double, 3> p = {0, 0, 0};
  for (int b = 0; b < bodies.num_bodies(); ++b)
  {
    const bodies::Body& body = bodies.body(b);
    Eigen::VectorXd vb(body.num_dofs());
    for (std::size_t k = 0; k < body.nodes.size(); ++k)
      for (int c = 0; c < 3; ++c)
        vb[3 * k + c] = v[3 * body.nodes[k] + c];
    const Eigen::VectorXd Mv =
        bodies::symmetric_product(bodies.consistent_mass()[b], vb);
    for (std::size_t k = 0; k < body.nodes.size(); ++k)
      for (int c = 0; c < 3; ++c)
        p[c] += Mv[3 * k + c];
  }
  return p;
}
} // namespace softpack::test
