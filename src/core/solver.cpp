#include "solver.h"

namespace drape {

std::unique_ptr<Solver> make_solver(Method method) {
  switch (method) {
    case Method::symplectic: return make_symplectic();
  }
  return nullptr;
}

}  // namespace drape
