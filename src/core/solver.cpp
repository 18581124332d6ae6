#include "solver.h"

namespace drape {

std::unique_ptr<Solver> make_solver(Method method) {
  switch (method) {
    case Method::symplectic: return make_symplectic();
    case Method::implicit: return make_implicit();
    case Method::xpbd: return make_xpbd();
    case Method::fast: return make_fast();
  }
  return nullptr;
}

}  // namespace drape
