#include "sim/mesh_bodies.hpp"

#include "core/errors.hpp"

namespace varsph {

template <int D>
void sample_mesh_body(const scene::Scene& s, std::size_t index, std::vector<Vec<D>>&, std::vector<Vec<D>>&) {
  throw InputError(s.file.string() + ": bodies." + std::to_string(index) +
                   ": mesh bodies need the geometry module, which this build does not include");
}

template void sample_mesh_body<2>(const scene::Scene&, std::size_t, std::vector<Vec<2>>&, std::vector<Vec<2>>&);
template void sample_mesh_body<3>(const scene::Scene&, std::size_t, std::vector<Vec<3>>&, std::vector<Vec<3>>&);

}  // namespace varsph
