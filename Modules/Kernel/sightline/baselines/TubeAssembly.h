// SPDX-License-Identifier: BSD-3-Clause
// Synthetic tube data for benchmarks and demos, the kind the generalized-tube paper measures
// (Han et al. 2019, Section 6): neurons (a soma and tapering, bifurcating dendrites and an
// axon), assemblies of randomly placed and rotated copies of a base neuron, and bundles of
// smooth non-branching streamlines (tractography-like). Real reconstructions (SWC files) can be
// assembled the same way.
#pragma once

#include "sightline/math/Math.h"

#include <cstdint>
#include <vector>

namespace sightline
{
/// Control points of tubes in the layout TubeSet takes: -1 starts a tube.
struct TubeTree
{
  std::vector<vec3> points;
  std::vector<float> radii;
  std::vector<std::int64_t> predecessors;
  /// One RGBA8 colour per point (packRGBA8), or empty.
  std::vector<std::uint32_t> colors;

  std::size_t size() const { return points.size(); }
  /// Points that have a predecessor.
  std::size_t linkCount() const;
  Box3 bounds() const;
  /// Appends `other` moved by `transform` (rotation and translation), with its links.
  void append(const TubeTree& other, const glm::mat4& transform, std::uint32_t color);
};

/// A neuron of about `links` links in micrometres: soma of radius 8 at the origin, 6 primary
/// dendrites and an axon growing by 2-4 um steps with persistent random directions, radii
/// tapering from 1.5 towards 0.25, branching at random (children thinner by Rall's 3/2 law).
TubeTree syntheticNeuron(std::size_t links, unsigned seed);

/// `copies` copies of `base`, each rotated about a random axis and placed uniformly at random in
/// a cube whose edge grows with the cube root of the count so that density stays constant
/// (`spacing` is the edge per neuron, in the base's units). Each copy gets a colour of its own.
/// Throws std::invalid_argument if the result would exceed 2^31 - 1 points.
TubeTree neuronAssembly(const TubeTree& base, std::size_t copies, float spacing, unsigned seed);

/// `lines` smooth non-branching streamlines of `linksPerLine` unit-length links in a cube of
/// edge `edge`, with radii varying smoothly in [0.6, 1.4] x `radius` along each line (a
/// tractography stand-in with a radius-encoded attribute), one colour per line.
TubeTree syntheticStreamlines(std::size_t lines, std::size_t linksPerLine, float edge,
  float radius, unsigned seed);
} // namespace sightline
