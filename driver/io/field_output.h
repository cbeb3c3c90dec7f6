#pragma once

#include <bodies/BodySet.h>
#include <dolfinx/io/XDMFFile.h>
#include <filesystem>
#include <memory>

namespace softpack::io
{

/// Fields for ParaView: `fields.xdmf` + `fields.h5` holding the mesh, the
/// displacement (P1, "displacement"), the strain-energy density (DG0,
/// "Psi", J/m^3, per reference volume) and the particle id (DG0,
/// "particle") at each written time.
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
  std::unique_ptr<dolfinx::io::XDMFFile> _file;
  std::shared_ptr<dolfinx::fem::Function<double>> _psi, _particle;
  std::vector<double> _cell_area;
};

} // namespace softpack::io
