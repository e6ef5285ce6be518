#pragma once
// Builds a frame description from the particle registry and the scene's output.fields.
#include "core/errors.hpp"
#include "io/frame_data.hpp"
#include "sim/simulation.hpp"

namespace varsph {

template <int D>
io::FrameData frame_from(const Simulation<D>& sim, const std::vector<std::string>& fields, bool float64) {
  io::FrameData f;
  f.dimension = D;
  f.positions = sim.store().find("position");
  for (const auto& name : fields) {
    const FieldBase* fb = sim.store().find(name);
    if (!fb) throw InputError(sim.scene().file.string() + ": key 'output.fields': no particle field named '" +
                              name + "' in this scene");
    f.arrays.push_back({name, fb, fb->components() == D && D >= 2 && fb->scalar_type() != ScalarType::Int64 &&
                                      fb->scalar_type() != ScalarType::Int32 && fb->components() > 1});
  }
  f.float64 = float64;
  f.time = sim.time();
  f.step = sim.step();
  f.dx = sim.scene().spacing;
  f.h = sim.scene().h;
  f.rho0 = sim.scene().rho0;
  f.c0 = sim.scene().c0;
  f.support_radius = double(sim.rates().support());
  f.kernel = kernels::to_string(sim.scene().kernel);
  return f;
}

}  // namespace varsph
