// Dropping the negligible couplings of the Delassus operator: within one
// time step a mass-dominated body's compliance decays over a few element
// sizes, so contacts on opposite sides of a disk do not couple; every block
// kept is exactly the full operator's.
#include <bodies/BodySet.h>
#include <bodies/material_parameters.h>
#include <cmath>
#include <compliance/contact_operator.h>
#include <compliance/delassus.h>
#include <compliance/effective_stiffness.h>
#include <detection/detection.h>
#include <gtest/gtest.h>
#include <material_registry.h>
#include <mesh_fixtures.h>

using namespace softpack;

TEST(DelassusDrop, FarContactsOnOneDiskDoNotCoupleAndKeptBlocksAreExact)
{
  const double R = 0.01, mu = 0.15e6, rho = 1180;
  bodies::BodySet bodies(test::bodies_mesh({test::disk(0, 0, R, 8)}),
                         forms::find_material("neo_hookean"),
                         bodies::plane_strain_parameters(mu), rho);
  // Two plates touching the disk at its poles.
  const std::vector<dynamics::Wall> walls = {
      {"bottom", {0, -R - 1e-6}, {0, 1}, {0, 0}},
      {"top", {0, R + 1e-6}, {0, -1}, {0, 0}}};
  dynamics::DetectionOptions detection;
  detection.alert_distance = 2e-3; // a few nodes at each pole
  const std::vector<double> x(bodies.reference_coordinates().begin(),
                              bodies.reference_coordinates().end());
  const std::vector<dynamics::Contact> contacts =
      dynamics::detect_contacts(bodies, x, walls, detection);
  const dynamics::ContactOperator H(contacts, walls);

  // The paper case's iteration matrix at h = 72 us, theta = 1/2.
  const double h = 7.2e-5, th = 0.5, alpha = 30, beta = 1e-5;
  dynamics::EffectiveStiffness kbar(bodies, false);
  std::vector<bodies::BodyMatrix> K = bodies.create_matrices();
  bodies.tangent(K);
  kbar.factorize(K, 1 + h * th * alpha, h * th * beta + h * h * th * th);

  const contact::DelassusMatrix full =
      dynamics::build_delassus(bodies, H, kbar);
  const contact::DelassusMatrix kept =
      dynamics::build_delassus(bodies, H, kbar, 1e-9);

  int top = 0, bottom = 0, dropped = 0;
  double cross = 0; // largest relative top-bottom coupling
  for (std::size_t a = 0; a < contacts.size(); ++a)
  {
    (contacts[a].wall == 1 ? top : bottom)++;
    EXPECT_EQ(full.diagonal(a), kept.diagonal(a));
    const auto cols = full.row_columns(a);
    const auto blocks = full.row_blocks(a);
    const auto kept_cols = kept.row_columns(a);
    for (std::size_t k = 0; k < cols.size(); ++k)
    {
      const std::size_t b = cols[k];
      const double relative =
          blocks[k].norm() /
          std::sqrt(full.diagonal(a).norm() * full.diagonal(b).norm());
      if (contacts[a].wall != contacts[b].wall)
        cross = std::max(cross, relative);
      auto it = std::find(kept_cols.begin(), kept_cols.end(), cols[k]);
      if (it == kept_cols.end())
      {
        ++dropped;
        continue;
      }
      EXPECT_EQ(kept.row_blocks(a)[it - kept_cols.begin()], blocks[k]);
    }
  }
  ASSERT_GT(top, 1);
  ASSERT_GT(bottom, 1);
  // Contacts 2R apart barely feel each other within a step (measured 1e-9
  // on this coarse mesh, 8 elements per radius: a thousandth of the
  // tolerance the fast settings solve contacts to) ...
  EXPECT_LT(cross, 1e-8);
  // ... so those blocks go, while neighbours at one pole stay coupled.
  EXPECT_GE(dropped, 2 * top * bottom);
  // A pair goes as one: W_ab is kept exactly when W_ba is (a distributed
  // run's plan derives what a rank sends from the rows it holds), at any
  // tolerance.
  for (const double tolerance : {1e-9, 1e-6, 1e-4, 1e-3, 1e-2, 1e-1})
  {
    const contact::DelassusMatrix W =
        dynamics::build_delassus(bodies, H, kbar, tolerance);
    for (std::size_t a = 0; a < contacts.size(); ++a)
      for (std::size_t k = 0; k < W.row_columns(a).size(); ++k)
      {
        const std::int32_t b = W.row_columns(a)[k];
        const auto back = W.row_columns(b);
        const auto at = std::find(back.begin(), back.end(), a);
        ASSERT_NE(at, back.end())
            << "W_" << a << "," << b << " kept without W_" << b << "," << a
            << " at tolerance " << tolerance;
        // ... and W_ba is W_ab^T to the last bit (one computation per pair)
        EXPECT_EQ(W.row_blocks(b)[at - back.begin()],
                  W.row_blocks(a)[k].transpose().eval())
            << a << "," << b;
      }
  }
  EXPECT_LT(kept.num_offdiagonal_blocks(), full.num_offdiagonal_blocks());
  EXPECT_GE(kept.num_offdiagonal_blocks(),
            static_cast<std::size_t>(top * (top - 1) + bottom * (bottom - 1)));
  std::printf("contacts %d + %d, blocks %zu -> %zu, largest cross coupling "
              "%.1e\n",
              top, bottom, full.num_offdiagonal_blocks(),
              kept.num_offdiagonal_blocks(), cross);
}
