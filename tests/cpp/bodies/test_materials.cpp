// The compiled UFL materials against analytic plane-strain energies, and
// their derivatives against finite differences.
#include "mesh_fixtures.h"
#include <bodies/BodySet.h>
#include <bodies/material_parameters.h>
#include <cmath>
#include <fstream>
#include <functional>
#include <gtest/gtest.h>
#include <map>
#include <material_defaults.h>
#include <material_registry.h>
#include <nlohmann/json.hpp>
#include <random>

using namespace softpack;

namespace
{
constexpr double mu = 0.15e6, lmbda = 0.3e6, rho = 1180, R = 0.01;

using Matrix2 = std::array<double, 4>; // row-major F

bodies::BodySet make_disk(const std::string& material, int rings = 6)
{
  // mu and lambda where the law has them (the analytic energies below use
  // them); its declared defaults for its other parameters
  forms::ParameterValues given;
  for (const forms::ParameterDefault& p : forms::parameter_defaults(material))
    for (const auto& [name, value] : bodies::plane_strain_parameters(mu, lmbda))
      if (name == p.name)
        given[name] = value;
  return bodies::BodySet(test::bodies_mesh({test::disk(0.02, -0.01, R, rings)}),
                         forms::find_material(material),
                         forms::with_defaults(material, given), rho);
}

/// Analytic plane-strain energy densities (F33 = 1).
double psi_neo_hookean(const Matrix2& F)
{
  const double I1 = F[0] * F[0] + F[1] * F[1] + F[2] * F[2] + F[3] * F[3] + 1;
  const double J = F[0] * F[3] - F[1] * F[2];
  return mu / 2 * (I1 - 3) - mu * std::log(J) +
         lmbda / 2 * std::log(J) * std::log(J);
}

double psi_saint_venant_kirchhoff(const Matrix2& F)
{
  // E = (F^T F - I)/2
  const double E00 = (F[0] * F[0] + F[2] * F[2] - 1) / 2;
  const double E11 = (F[1] * F[1] + F[3] * F[3] - 1) / 2;
  const double E01 = (F[0] * F[1] + F[2] * F[3]) / 2;
  const double trE = E00 + E11;
  return lmbda / 2 * trE * trE + mu * (E00 * E00 + E11 * E11 + 2 * E01 * E01);
}

/// u = (F - I) X + c on every node.
void set_affine(bodies::BodySet& bodies, const Matrix2& F,
                std::array<double, 2> c = {0, 0})
{
  std::span<const double> X = bodies.reference_coordinates();
  std::span<double> u = bodies.displacement();
  for (std::size_t i = 0; i < X.size() / 2; ++i)
  {
    const double x = X[2 * i], y = X[2 * i + 1];
    u[2 * i] = (F[0] - 1) * x + F[1] * y + c[0];
    u[2 * i + 1] = F[2] * x + (F[3] - 1) * y + c[1];
  }
}

double total_reference_area(const bodies::BodySet& bodies)
{
  double a = 0;
  for (int b = 0; b < bodies.num_bodies(); ++b)
    a += bodies.body(b).reference_area;
  return a;
}

const std::vector<std::pair<std::string, Matrix2>> deformations = {
    {"uniaxial stretch", {1.3, 0, 0, 1}},
    {"uniaxial compression", {0.75, 0, 0, 1}},
    {"biaxial stretch", {1.2, 0, 0, 0.85}},
    {"simple shear", {1, 0.4, 0, 1}},
    {"general", {1.1, 0.2, -0.15, 0.9}},
};

void check_homogeneous(const std::string& material,
                       const std::function<double(const Matrix2&)>& psi)
{
  bodies::BodySet bodies = make_disk(material);
  const double area = total_reference_area(bodies);
  for (const auto& [name, F] : deformations)
  {
    set_affine(bodies, F, {1e-3, -2e-3});
    const double expected = psi(F) * area;
    EXPECT_NEAR(bodies.strain_energy() / expected, 1.0, 1e-10)
        << material << ", " << name;
    const std::vector<double> cellwise = bodies.body_strain_energy();
    EXPECT_NEAR(cellwise[0] / expected, 1.0, 1e-10) << material << ", " << name;
  }
}

/// A smooth, finite, non-affine displacement field.
void set_wavy(bodies::BodySet& bodies, double amplitude)
{
  std::span<const double> X = bodies.reference_coordinates();
  std::span<double> u = bodies.displacement();
  for (std::size_t i = 0; i < X.size() / 2; ++i)
  {
    const double x = X[2 * i] / R, y = X[2 * i + 1] / R;
    u[2 * i] = amplitude * R * std::sin(1.3 * x + 0.4 * y);
    u[2 * i + 1] = amplitude * R * std::cos(0.7 * x - 1.1 * y) * x;
  }
}

std::vector<double> random_direction(std::size_t n, double scale)
{
  std::mt19937 gen(42);
  std::uniform_real_distribution<double> dist(-scale, scale);
  std::vector<double> w(n);
  for (double& wi : w)
    wi = dist(gen);
  return w;
}

double norm(const std::vector<double>& v)
{
  double s = 0;
  for (double x : v)
    s += x * x;
  return std::sqrt(s);
}
} // namespace

TEST(Materials, RegistryHoldsTheShippedMaterials)
{
  // each law with the parameters its forms/materials/*.py declares
  const std::map<std::string, std::vector<std::string>> shipped = {
      {"gent", {"gent_jm", "lame_lambda", "shear_modulus"}},
      {"mooney_rivlin", {"c01", "c10", "lame_lambda"}},
      {"neo_hookean", {"lame_lambda", "shear_modulus"}},
      {"saint_venant_kirchhoff", {"lame_lambda", "shear_modulus"}}};
  const std::vector<std::string> names = forms::material_names();
  for (const auto& [name, parameters] : shipped)
  {
    ASSERT_NE(std::find(names.begin(), names.end(), name), names.end()) << name;
    std::vector<std::string> p =
        forms::material_parameters(forms::find_material(name));
    std::sort(p.begin(), p.end());
    EXPECT_EQ(p, parameters) << name;
  }
}

// build/forms/materials.json (written by forms/registry.py from the
// `parameters` dicts) declares exactly the constants FFCx compiled.
TEST(Materials, RegistryJsonMatchesTheCompiledConstants)
{
  std::ifstream in(SOFTPACK_MATERIALS_JSON);
  ASSERT_TRUE(in) << SOFTPACK_MATERIALS_JSON;
  const nlohmann::json registry = nlohmann::json::parse(in);
  EXPECT_EQ(registry.at("schema_version"), 2);
  const nlohmann::json& materials = registry.at("materials");
  EXPECT_EQ(materials.size(), forms::material_names().size());
  for (const std::string& name : forms::material_names())
  {
    std::vector<std::string> compiled =
        forms::material_parameters(forms::find_material(name));
    std::sort(compiled.begin(), compiled.end());
    std::vector<std::string> declared;
    for (const auto& item : materials.at(name).at("parameters").items())
    {
      declared.push_back(item.key());
      for (const char* field : {"unit", "range", "default", "doc"})
        EXPECT_TRUE(item.value().contains(field)) << name << " " << field;
    }
    std::sort(declared.begin(), declared.end());
    EXPECT_EQ(declared, compiled) << name;
  }
  const nlohmann::json& nh = materials.at("neo_hookean").at("parameters");
  EXPECT_EQ(nh.at("shear_modulus").at("default"), 0.15e6);
  EXPECT_EQ(nh.at("lame_lambda").at("default"), "2 * shear_modulus");
}

TEST(Materials, UnknownMaterialNamesTheRegisteredOnes)
{
  try
  {
    forms::find_material("mooney");
    FAIL() << "expected an exception";
  }
  catch (const std::invalid_argument& e)
  {
    EXPECT_NE(std::string(e.what()).find("neo_hookean"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("mooney"), std::string::npos);
  }
}

TEST(Materials, MissingOrUnknownParameterIsAnError)
{
  auto mesh = test::bodies_mesh({test::disk(0, 0, R, 2)});
  const auto& nh = forms::find_material("neo_hookean");
  auto message = [&](const std::map<std::string, double>& parameters)
  {
    try
    {
      bodies::BodySet(mesh, nh, parameters, rho);
    }
    catch (const std::invalid_argument& e)
    {
      return std::string(e.what());
    }
    return std::string();
  };
  const std::string missing = message({{"shear_modulus", mu}});
  EXPECT_NE(missing.find("material.parameters.lame_lambda"), std::string::npos)
      << missing;
  const std::string unknown =
      message({{"shear_modulus", mu}, {"lame_lambda", lmbda}, {"nu", 0.3}});
  EXPECT_NE(unknown.find("material.parameters.nu"), std::string::npos)
      << unknown;
  // Both name the law's parameters.
  for (const std::string& m : {missing, unknown})
  {
    EXPECT_NE(m.find("shear_modulus, lame_lambda"), std::string::npos) << m;
  }
}

TEST(Materials, EffectivePlaneStrainParametersDefaultToNuOneThird)
{
  const auto p = bodies::plane_strain_parameters(mu);
  EXPECT_DOUBLE_EQ(p.at("lame_lambda"), 2 * mu);
  EXPECT_NEAR(bodies::poisson_ratio(p.at("shear_modulus"), p.at("lame_lambda")),
              1.0 / 3, 1e-15);
  EXPECT_DOUBLE_EQ(
      bodies::plane_strain_parameters(mu, 5 * mu).at("lame_lambda"), 5 * mu);
  EXPECT_THROW(bodies::plane_strain_parameters(-1), std::invalid_argument);
}

TEST(Materials, NeoHookeanHomogeneousEnergyIsAnalytic)
{
  check_homogeneous("neo_hookean", psi_neo_hookean);
}

TEST(Materials, SaintVenantKirchhoffHomogeneousEnergyIsAnalytic)
{
  check_homogeneous("saint_venant_kirchhoff", psi_saint_venant_kirchhoff);
}

TEST(Materials, LargeRigidRotationStoresNoEnergy)
{
  for (const std::string& material : forms::material_names())
  {
    bodies::BodySet bodies = make_disk(material);
    const double t = 1.0; // radians
    set_affine(bodies, {std::cos(t), -std::sin(t), std::sin(t), std::cos(t)},
               {0.05, -0.02});
    const double area = total_reference_area(bodies);
    EXPECT_LT(std::abs(bodies.strain_energy()) / (mu * area), 1e-12)
        << material;
    std::vector<double> f(bodies.num_dofs());
    bodies.internal_force(f);
    // Nodal forces scale like mu * R (per unit length).
    EXPECT_LT(norm(f) / (mu * R), 1e-10) << material;
  }
}

TEST(Materials, ResidualIsTheDerivativeOfTheEnergy)
{
  for (const std::string& material : forms::material_names())
  {
    bodies::BodySet bodies = make_disk(material);
    set_wavy(bodies, 0.08);
    std::vector<double> u0(bodies.displacement().begin(),
                           bodies.displacement().end());
    const std::vector<double> w = random_direction(u0.size(), R);
    std::vector<double> f(u0.size());
    bodies.internal_force(f);
    double directional = 0;
    for (std::size_t i = 0; i < w.size(); ++i)
      directional += f[i] * w[i];

    // Central differences: truncation error O(eps^2) relative to the
    // perturbation, round-off O(1e-16 E / eps); eps = 1e-5 balances both.
    const double eps = 1e-5;
    std::span<double> u = bodies.displacement();
    auto energy_at = [&](double s)
    {
      for (std::size_t i = 0; i < u0.size(); ++i)
        u[i] = u0[i] + s * w[i];
      return bodies.strain_energy();
    };
    const double fd = (energy_at(eps) - energy_at(-eps)) / (2 * eps);
    EXPECT_LT(std::abs(fd - directional) / std::abs(directional), 1e-6)
        << material;
  }
}

TEST(Materials, TangentIsTheDerivativeOfTheResidual)
{
  for (const std::string& material : forms::material_names())
  {
    bodies::BodySet bodies = make_disk(material);
    set_wavy(bodies, 0.08);
    std::vector<double> u0(bodies.displacement().begin(),
                           bodies.displacement().end());
    const std::vector<double> w = random_direction(u0.size(), R);

    std::vector<bodies::BodyMatrix> K = bodies.create_matrices();
    bodies.tangent(K);
    const bodies::Body& body = bodies.body(0);
    Eigen::VectorXd wb(body.num_dofs());
    for (std::size_t k = 0; k < body.nodes.size(); ++k)
      for (int c = 0; c < 2; ++c)
        wb[2 * k + c] = w[2 * body.nodes[k] + c];
    const Eigen::VectorXd Kw = bodies::symmetric_product(K[0], wb);

    const double eps = 1e-5;
    std::span<double> u = bodies.displacement();
    auto force_at = [&](double s)
    {
      for (std::size_t i = 0; i < u0.size(); ++i)
        u[i] = u0[i] + s * w[i];
      std::vector<double> f(u0.size());
      bodies.internal_force(f);
      return f;
    };
    const std::vector<double> fp = force_at(eps), fm = force_at(-eps);
    double err2 = 0;
    for (std::size_t k = 0; k < body.nodes.size(); ++k)
      for (int c = 0; c < 2; ++c)
      {
        const std::size_t g = 2 * body.nodes[k] + c;
        const double fd = (fp[g] - fm[g]) / (2 * eps);
        err2 += (fd - Kw[2 * k + c]) * (fd - Kw[2 * k + c]);
      }
    EXPECT_LT(std::sqrt(err2) / Kw.norm(), 1e-6) << material;
  }
}
