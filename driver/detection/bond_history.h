#pragma once

#include "contact_history.h"
#include "friction_table.h"

#include <array>
#include <cstdint>
#include <map>
#include <span>
#include <utility>
#include <vector>

/// The intact bonds of the bonded law (docs/contact_laws.md): what the
/// time stepping remembers of them from one step to the next.
namespace softpack::dynamics
{

/// A step's intact bonds: which of its contacts, and the gap each bond
/// holds (the gap at its bonding)
struct StepBonds
{
  std::vector<std::int32_t> contacts;
  std::vector<double> gap;
};

/// The intact bonds by contact identity (ContactKey), each with the gap it
/// holds. Bonds form (form()) at the first step of a run, or of a run
/// continued from a state in which none had formed, or at the first step of
/// a stage with bond = true (set_formed()); a bond that
/// breaks (a reaction on its envelope, or its contact not detected) is
/// gone for good.
class BondHistory
{
public:
  /// One entry as stored in a state file: the key and the held gap (m)
  using Entry = std::pair<std::array<int, 3>, double>;

  /// Bond every contact of a bonded pair whose gap is at most its pair's
  /// bonding distance, and mark the bonds formed.
  void form(const FrictionTable& table, const std::vector<Contact>& contacts);

  /// true once form() ran (in this run or the one whose state it restored)
  bool formed() const { return _formed; }

  /// Mark the bonds formed (false: form() is due at the next step, as at a
  /// stage with bond = true; true without a bond: none forms at the first
  /// step, as in a program whose stages form them)
  void set_formed(bool formed) { _formed = formed; }

  /// The intact bonds among a step's contacts
  StepBonds intact(const std::vector<Contact>& contacts) const;

  /// Keep the bonds that held over a step: drop every bond whose contact
  /// is not among the step's, and those listed as broken.
  /// @param[in] contacts The step's contacts
  /// @param[in] step The step's bonds (intact())
  /// @param[in] broken Per bond of `step`: true when it broke
  /// @return The number of bonds that broke
  int keep_intact(const std::vector<Contact>& contacts, const StepBonds& step,
                  std::span<const char> broken);

  /// Number of intact bonds
  std::size_t size() const { return _gap.size(); }

  /// Every intact bond, in key order
  std::vector<Entry> entries() const;

  /// Replace the bonds by saved entries (entries()) and the formed flag.
  void restore(const std::vector<Entry>& entries, bool formed);

private:
  std::map<ContactKey, double> _gap;
  bool _formed = false;
};

} // namespace softpack::dynamics
