#include "forces/bending.h"

#include <cmath>

namespace drape::forces {

double bending_energy(const ClothModel& model, const std::vector<Vec3>& x) {
  double e = 0.0;
  for (const BendingElement& b : model.bending) e += bending_energy(b, x);
  return e;
}

void bending_row_sums(const ClothModel& model, std::vector<double>& stiffness,
                      std::vector<double>& damping) {
  for (const BendingElement& b : model.bending) {
    const double sum = std::abs(b.w[0]) + std::abs(b.w[1]) + std::abs(b.w[2]) + std::abs(b.w[3]);
    for (int k = 0; k < 4; ++k) {
      stiffness[b.v[k]] += b.stiffness * std::abs(b.w[k]) * sum;
      damping[b.v[k]] += b.damping * std::abs(b.w[k]) * sum;
    }
  }
}

}  // namespace drape::forces
