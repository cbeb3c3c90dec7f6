#pragma once

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <unistd.h>

/// driver.json documents written by hand (docs/contract.md section 4), as
/// python/softpack/simulation/driver_input.py writes them.
namespace softpack::test
{

/// A box [0, length] x [0, width] whose right wall moves at -speed along x,
/// `bodies` bodies of species 0, the schema's defaults elsewhere.
inline nlohmann::json driver_json(const std::filesystem::path& directory,
                                  const std::filesystem::path& mesh, int bodies,
                                  double length = 0.286, double width = 0.202,
                                  double speed = 0.1)
{
  nlohmann::json doc = nlohmann::json::parse(R"({
    "schema_version": 2,
    "initial_state": null,
    "scene": {
      "model": {"thickness": 0.015},
      "box": {"enabled": true, "length": 0, "width": 0},
      "packing": {"seed": 0, "gap": 0.0001},
      "species": [{"name": "small", "shape": "disk", "diameter": 0.02,
                   "count": 0}],
      "mesh": {"element_size": 0.001065},
      "bodies": {"mesh": "", "species": []}
    },
    "material": {"law": "neo_hookean", "density": 1180.0, "rigid": false,
                 "parameters": {"shear_modulus": 150000.0,
                                "lame_lambda": 300000.0}},
    "materials": [],
    "walls": [
      {"name": "left", "point": [0, 0], "normal": [1, 0], "velocity": [0, 0],
       "control": "velocity", "pressure": 0, "force": 0, "mass": 1},
      {"name": "right", "point": [0, 0], "normal": [-1, 0],
       "velocity": [0, 0],
       "control": "velocity", "pressure": 0, "force": 0, "mass": 1},
      {"name": "bottom", "point": [0, 0], "normal": [0, 1],
       "velocity": [0, 0],
       "control": "velocity", "pressure": 0, "force": 0, "mass": 1},
      {"name": "top", "point": [0, 0], "normal": [0, -1], "velocity": [0, 0],
       "control": "velocity", "pressure": 0, "force": 0, "mass": 1}
    ],
    "stages": [],
    "stop": {"packing_fraction": 0.88, "max_time": 1.43, "steps": 0,
             "base_area_fraction": 0.0},
    "contact": {"friction": 0.3, "alert_distance": 2e-4,
                "max_penetration": 5e-4, "nlgs_tolerance": 1e-6,
                "nlgs_max_sweeps": 2000, "nlgs_relaxation": 1.7,
                "nlgs_order": "alternate", "nlgs_update": "auto", "nlgs_condensation": "auto", "nlgs_extrapolation": "auto",
                "delassus_drop_tolerance": 1e-9},
    "friction": [],
    "time": {"time_step": 7.2e-5, "max_step_factor": 1.0, "theta": 0.55,
             "mass": "consistent",
             "newton_tolerance": 1e-4, "newton_max_iterations": 20,
             "full_newton": false, "tangent_reuse_steps": 50,
             "refactor_above_iterations": 5},
    "damping": {"alpha": 30.0, "beta": 1e-5},
    "gravity": {"acceleration": [0.0, 0.0]},
    "output": {"every_steps": 12, "fields": true, "fields_every": 10,
               "state": true},
    "parallel": {"rebalance_tolerance": 0.1},
    "cell": {"enabled": false, "a1": [0.1, 0.0], "a2": [0.0, 0.1],
             "velocity_gradient_x": [0.0, 0.0],
             "velocity_gradient_y": [0.0, 0.0], "control_xx": "velocity",
             "control_yy": "velocity", "stress_xx": 0.0, "stress_yy": 0.0,
             "control_xy": "velocity", "stress_xy": 0.0,
             "control_mean": "velocity", "stress_mean": 0.0, "stress_rate": 0.0, "mass": 1.0,
             "damping_time": 0.0}
  })");
  doc["directory"] = directory.string();
  doc["scene"]["box"]["length"] = length;
  doc["scene"]["box"]["width"] = width;
  doc["scene"]["species"][0]["count"] = bodies;
  doc["scene"]["bodies"]["mesh"] = mesh.string();
  doc["scene"]["bodies"]["species"] = std::vector<int>(bodies, 0);
  doc["walls"][1]["point"] = {length, 0.0};
  doc["walls"][1]["velocity"] = {-speed, 0.0};
  doc["walls"][3]["point"] = {0.0, width};
  return doc;
}

/// Write `doc` as `path`.
/// A stage's cell drive (its `cell` table) at the [cell] defaults
inline nlohmann::json stage_cell()
{
  return nlohmann::json::parse(R"({
    "velocity_gradient_x": [0.0, 0.0], "velocity_gradient_y": [0.0, 0.0],
    "control_xx": "velocity", "control_yy": "velocity",
    "control_xy": "velocity", "control_mean": "velocity", "stress_xx": 0.0,
    "stress_yy": 0.0, "stress_xy": 0.0, "stress_mean": 0.0,
    "stress_rate": 0.0})");
}

inline void write_json(const nlohmann::json& doc,
                       const std::filesystem::path& path)
{
  std::filesystem::create_directories(path.parent_path());
  std::ofstream(path) << doc.dump(2) << '\n';
}

/// A fresh empty directory under the system's temporary directory, one per
/// process (CTest runs the tests of one executable in parallel processes).
inline std::filesystem::path fresh_directory(const std::string& name)
{
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() /
      ("softpack-test-" + name + "-" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

} // namespace softpack::test
