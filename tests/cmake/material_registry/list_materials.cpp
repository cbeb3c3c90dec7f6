// Print each registered material and its parameters, one per line.
#include <cstdio>
#include <material_registry.h>

int main()
{
  for (const auto& name : softpack::forms::material_names())
  {
    std::printf("%s:", name.c_str());
    for (const auto& p : softpack::forms::material_parameters(
             softpack::forms::find_material(name)))
      std::printf(" %s", p.c_str());
    std::printf("\n");
  }
  return 0;
}
