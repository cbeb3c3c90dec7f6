#pragma once

#include <bodies/BodySet.h>
#include <filesystem>
#include <io/h5_helpers.h>
#include <memory>
#include <span>
#include <string>
#include <vector>

namespace softpack::io
{

/// Fields for ParaView and meshio: `fields.xdmf` + `fields.h5` holding the
/// mesh, the displacement ("displacement", at the nodes), the strain-energy
/// density ("Psi", J/m^3 per reference volume, by cell) and the particle id
/// ("particle", by cell) at each written time.
///
/// The HDF5 datasets keep the layout dolfinx's XDMFFile gave them (read by
/// python/softpack/analysis/fields.py): /Mesh/mesh/geometry (nodes x 2),
/// /Mesh/mesh/topology (cells x 3, int64), /Function/<name>/<time> (nodes x
/// 3 or cells x 1), the time written with 17 digits, '.' as '_'. They are
/// written from the BodySet's arrays (nodes in its DOF order, cells as
/// Body::cells numbers them): the run holds no dolfinx mesh to hand to
/// XDMFFile. The XML holds one temporal collection whose grids hold every
/// field at their time (meshio's TimeSeriesReader follows only one), the
/// first grid holding the mesh and the others including it; it is replaced
/// atomically after each write, and fields.h5 flushed, so that a killed run
/// keeps the frames its fields.xdmf lists.
///
/// A run continued from its own state (a resume) continues its fields.h5:
/// the frames up to the state's time stay, the later ones (written before
/// the kill, past the state) go, and the resumed driver's frames follow in
/// the same file, so that every frame of every segment reads as one time
/// series (fields.xdmf lists them all).
class FieldOutput
{
public:
  /// @param[in] directory Output directory
  /// @param[in] bodies The bodies (nodes, cells, reference coordinates),
  /// every node stored (before BodySet::keep_storage)
  /// @param[in] continued A run continued from a state: an existing
  /// fields.h5 of the same mesh is kept (continue_after), not replaced
  /// @throws std::runtime_error if fields.h5 cannot be created, or the one
  /// to continue is not of this mesh
  /// @throws std::logic_error if the bodies store some nodes only
  FieldOutput(const std::filesystem::path& directory,
              const bodies::BodySet& bodies, bool continued = false);
  ~FieldOutput();

  /// Keep the frames at times up to t of a continued fields.h5 (the
  /// state's time) and drop the later ones.
  void continue_after(double t);

  /// Write the fields at time t (a frame at a time already written is
  /// replaced).
  /// @param[in] u Global displacement (2 entries per mesh node)
  /// @param[in] cell_energy Strain energy of each cell
  void write(std::span<const double> u, std::span<const double> cell_energy,
             double t);

private:
  /// Write fields.xdmf (atomically) for the times written so far.
  void write_xml() const;
  /// Flush fields.h5's buffers and metadata to disk
  void flush() const;
  /// Open the existing fields.h5 to continue it, its mesh checked; its
  /// frames' times read
  void open_existing(const std::filesystem::path& path);
  /// Remove the frame at time key `key` (its three datasets)
  void remove_frame(const std::string& key) const;

  std::filesystem::path _xdmf;
  std::size_t _num_nodes = 0, _num_cells = 0;
  std::vector<double> _times;
  std::unique_ptr<h5::Handle> _file;
  std::vector<double> _cell_area, _particle;
};

} // namespace softpack::io
