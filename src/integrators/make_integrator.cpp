// Integrator selection by name, once at setup.
#include "core/errors.hpp"
#include "integrators/predictor_corrector.hpp"
#include "integrators/rk4.hpp"
#include "integrators/symplectic_euler.hpp"
#include "integrators/variational.hpp"
#include "integrators/verlet.hpp"
#include "integrators/verlet_dsph.hpp"

namespace varsph {

template <int D>
std::unique_ptr<Integrator<D>> make_integrator(const scene::Scene& s) {
  if (s.integrator == "verlet") return std::make_unique<VerletIntegrator<D>>();
  if (s.integrator == "variational") return std::make_unique<VariationalIntegrator<D>>(s);
  // explicit schemes of the foundation notes (docs/integrators.md)
  if (s.integrator == "symplectic_euler") return std::make_unique<SymplecticEulerIntegrator<D>>();
  if (s.integrator == "predictor_corrector") return std::make_unique<PredictorCorrectorIntegrator<D>>();
  if (s.integrator == "rk4") return std::make_unique<Rk4Integrator<D>>();
  if (s.integrator == "verlet_dsph") return std::make_unique<VerletDsphIntegrator<D>>(s.euler_every);
  throw InputError(s.file.string() + ": key 'integrator.type': \"" + s.integrator +
                   "\" is not available in this build (available: \"verlet\", \"variational\", "
                   "\"symplectic_euler\", \"predictor_corrector\", \"rk4\", \"verlet_dsph\")");
}

template std::unique_ptr<Integrator<2>> make_integrator<2>(const scene::Scene&);
template std::unique_ptr<Integrator<3>> make_integrator<3>(const scene::Scene&);

}  // namespace varsph
