// The table of Coulomb coefficients (driver/dynamics/friction_table.h): one
// entry per pair of parties (species, then walls), symmetric, the default
// (the caller's [contact] friction) for every pair not set; species and
// parties out of range refused.
#include <detection/detection.h>
#include <detection/friction_table.h>
#include <gtest/gtest.h>
#include <stdexcept>

using softpack::dynamics::Contact;
using softpack::dynamics::FrictionTable;

namespace
{
Contact contact(int candidate, int antagonist, int wall)
{
  Contact c{};
  c.candidate_body = candidate;
  c.antagonist_body = antagonist;
  c.wall = wall;
  return c;
}
} // namespace

TEST(FrictionTable, PairsAreSymmetricAndTheRestKeepTheDefault)
{
  // bodies of species 0, 1, 1; two walls
  FrictionTable f({0, 1, 1}, 2, 2);
  EXPECT_EQ(f.species_party(1), 1);
  EXPECT_EQ(f.wall_party(1), 3);
  f.set(f.species_party(1), f.species_party(0), 0.2);
  f.set(f.wall_party(1), f.species_party(1), 0.8);
  EXPECT_EQ(f(contact(0, 1, -1), 0.3), 0.2);
  EXPECT_EQ(f(contact(2, 0, -1), 0.3), 0.2);
  EXPECT_EQ(f(contact(1, 2, -1), 0.3), 0.3); // species 1 with itself
  EXPECT_EQ(f(contact(2, -1, 1), 0.3), 0.8); // species 1 on wall 1
  EXPECT_EQ(f(contact(2, -1, 0), 0.3), 0.3); // species 1 on wall 0
  EXPECT_EQ(f(contact(0, -1, 1), 0.3), 0.3); // species 0 on wall 1
  // a pair set again takes the last value
  f.set(f.species_party(0), f.species_party(1), 0.0);
  EXPECT_EQ(f(contact(1, 0, -1), 0.3), 0.0);
}

TEST(FrictionTable, WithoutSpeciesEveryContactHasTheDefault)
{
  const FrictionTable f({}, 0, 4);
  EXPECT_EQ(f(contact(5, 7, -1), 0.4), 0.4);
  EXPECT_EQ(f(contact(5, -1, 3), 0.4), 0.4);
  // with species, a pair not set takes the default too
  EXPECT_EQ(FrictionTable({0}, 1, 4)(contact(0, -1, 3), 0.4), 0.4);
}

TEST(FrictionTable, OutOfRangeIsRefused)
{
  try
  {
    FrictionTable({0, 2}, 2, 1);
    FAIL() << "accepted species 2 of 2";
  }
  catch (const std::invalid_argument& e)
  {
    EXPECT_NE(std::string(e.what()).find("species 2 out of range"),
              std::string::npos)
        << e.what();
  }
  FrictionTable f({0, 1}, 2, 1);
  EXPECT_THROW(f.set(0, 3, 0.1), std::invalid_argument); // 3 parties
  EXPECT_THROW(f.set(-1, 0, 0.1), std::invalid_argument);
  EXPECT_THROW(f.set(0, 1, -0.1), std::invalid_argument);
  EXPECT_EQ(f(contact(0, 1, -1), 0.3), 0.3); // a refused set leaves the table
}
