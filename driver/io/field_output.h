#pragma once

#include <bodies/BodySet.h>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

namespace softpack::io
{

/// Fields for ParaView and meshio: `fields.xdmf`, the mesh in `fields.h5` and
/// one HDF5 file per written time in `fields/`, holding the displacement
/// ("displacement", at the nodes), the strain-energy density ("Psi", J/m^3
/// per reference volume, by cell) and the particle id ("particle", by cell).
///
/// The HDF5 datasets keep the layout dolfinx's XDMFFile gave them (read by
/// python/softpack/analysis/fields.py): fields.h5 holds /Mesh/mesh/geometry
/// (nodes x 2; 3D: x 3) and /Mesh/mesh/topology (cells x 3, int64; 3D:
/// tetrahedra, x 4); the frame of time
/// t, `fields/<key>.h5`, holds /Function/<name>/<key> (nodes x 3 or cells x
/// 1), the key being t written with 17 digits, '.' as '_'. They are written
/// from the BodySet's arrays (nodes in its DOF order, cells as Body::cells
/// numbers them): the run holds no dolfinx mesh to hand to XDMFFile. The XML
/// holds one temporal collection whose grids hold every field at their time
/// (meshio's TimeSeriesReader follows only one), the first grid holding the
/// mesh and the others including it.
///
/// Crash consistency: no file is ever modified in place. fields.h5 and each
/// frame are written under a temporary name, closed, and renamed; fields.xdmf
/// is replaced (by a rename) after the frame it lists. A driver killed at any
/// moment leaves every frame fields.xdmf lists whole (a frame renamed but not
/// yet listed is whole too; a temporary file is removed by the next driver).
///
/// A run continued from its own state (a resume) continues its fields: the
/// frames up to the state's time stay, the later ones (written before the
/// kill, past the state) go, and the resumed driver's frames follow, so that
/// every frame of every segment reads as one time series (fields.xdmf lists
/// them all). The frames an earlier version wrote inside fields.h5 are
/// listed too (removed past the state's time).
class FieldOutput
{
public:
  /// @param[in] directory Output directory
  /// @param[in] bodies The bodies (nodes, cells, reference coordinates),
  /// every node stored (before BodySet::keep_storage)
  /// @param[in] continued A run continued from a state: an existing
  /// fields.h5 of the same mesh and its frames are kept (continue_after),
  /// not replaced
  /// @throws std::runtime_error if fields.h5 cannot be written, or the one
  /// to continue is not of this mesh
  /// @throws std::logic_error if the bodies store some nodes only
  FieldOutput(const std::filesystem::path& directory,
              const bodies::BodySet& bodies, bool continued = false);

  /// Keep the frames at times up to t of continued fields (the state's
  /// time) and drop the later ones.
  void continue_after(double t);

  /// Write the fields at time t (a frame at a time already written is
  /// replaced).
  /// @param[in] u Global displacement (dim entries per mesh node)
  /// @param[in] cell_energy Strain energy of each cell
  void write(std::span<const double> u, std::span<const double> cell_energy,
             double t);

private:
  /// A written time and the file holding it, relative to the directory
  struct Frame
  {
    double time;
    std::string file;
  };

  /// Write fields.h5 (the mesh) and an empty fields/
  void create(const bodies::BodySet& bodies);
  /// Check the mesh of an existing fields.h5 and list its frames and those
  /// of fields/ (temporary files of a killed driver removed)
  void open_existing();
  /// Remove the frames an earlier version wrote in fields.h5 after time t
  void remove_inner_frames_after(double t) const;
  /// Write fields.xdmf (atomically) for the frames written so far.
  void write_xml() const;

  std::filesystem::path _directory;
  int _dim = 2; // the bodies' dimension: triangles or tetrahedra
  std::size_t _num_nodes = 0, _num_cells = 0;
  std::vector<Frame> _frames; // in ascending time
  std::vector<double> _cell_area, _particle;
};

} // namespace softpack::io
