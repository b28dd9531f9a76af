// SPDX-License-Identifier: BSD-3-Clause
// Rotations of real SH functions: the coefficients of the glyph turned by a 3x3 orthogonal
// matrix. Glyphs whose directions are given in an image's voxel axes (e.g. a DIPY fit with
// FSL-style b-vectors) are drawn in world space by turning them with the image's orientation.
#pragma once

#include "sightline/math/Math.h"

#include <glm/mat3x3.hpp>

#include <vector>

namespace sightline
{
class SHRotation
{
public:
  /// The map F -> G with G(w) = F(R^T w) for the canonical basis up to `order`: G is F turned
  /// by R. R must be orthogonal (a rotation, or a rotation with a reflection: even bands do not
  /// notice point reflections); throws std::invalid_argument otherwise or for a bad order.
  SHRotation(int order, const glm::dmat3& rotation);

  /// Turns `count = shCoefficientCount(order)` canonical coefficients (in and out may not alias).
  void apply(const double* coefficients, double* rotated) const;

  int order() const { return Order; }

private:
  int Order;
  /// One dense (2l+1)^2 block per even band l, row-major, concatenated.
  std::vector<double> Blocks;
};
} // namespace sightline
