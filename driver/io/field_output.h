#pragma once

#include <bodies/BodySet.h>
#include <dolfinx/io/XDMFFile.h>
#include <filesystem>
#include <memory>

namespace softpack::io
{

/// Fields for ParaView and meshio: `fields.xdmf` + `fields.h5` holding the
/// mesh, the displacement (P1, "displacement"), the strain-energy density
/// (DG0, "Psi", J/m^3, per reference volume) and the particle id (DG0,
/// "particle") at each written time.
///
/// dolfinx writes the HDF5 datasets (/Mesh/<mesh>/geometry, topology,
/// /Function/<name>/<time>, read by python/softpack/analysis/fields.py),
/// but its XML holds one temporal collection per function, which meshio's
/// TimeSeriesReader cannot follow (it reads only the last one). The XML is
/// therefore replaced after each write by one temporal collection whose
/// grids hold every field at their time, the first grid holding the mesh
/// and the others including it.
class FieldOutput
{
public:
  /// @param[in] comm The communicator of the bodies' mesh
  /// @param[in] directory Output directory
  /// @param[in] bodies The bodies (mesh, spaces)
  FieldOutput(MPI_Comm comm, const std::filesystem::path& directory,
              const bodies::BodySet& bodies);
  ~FieldOutput();

  /// Write the current state at time t.
  void write(const bodies::BodySet& bodies, double t);

private:
  /// Write fields.xdmf (atomically) for the times written so far.
  void write_xml() const;

  std::filesystem::path _xdmf;
  std::string _mesh_name;
  std::size_t _num_nodes = 0, _num_cells = 0;
  std::vector<double> _times;
  std::unique_ptr<dolfinx::io::XDMFFile> _file;
  std::shared_ptr<dolfinx::fem::Function<double>> _psi, _particle;
  std::vector<double> _cell_area;
};

} // namespace softpack::io
