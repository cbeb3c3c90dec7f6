#include "walls.h"

namespace softpack::dynamics
{

std::vector<Wall> box_walls(double x0, double x1, double y0, double y1,
                            double piston_speed)
{
  return {
      {"left", {x0, 0}, {1, 0}, {0, 0}},
      {"piston", {x1, 0}, {-1, 0}, {-piston_speed, 0}},
      {"bottom", {0, y0}, {0, 1}, {0, 0}},
      {"top", {0, y1}, {0, -1}, {0, 0}},
  };
}

} // namespace softpack::dynamics
