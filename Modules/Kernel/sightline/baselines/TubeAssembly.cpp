// SPDX-License-Identifier: BSD-3-Clause
#include "sightline/baselines/TubeAssembly.h"

#include "sightline/core/Geometry.h"

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>
#include <string>

namespace sightline
{
std::size_t TubeTree::linkCount() const
{
  return std::size_t(std::count_if(predecessors.begin(), predecessors.end(), [](std::int64_t p) { return p >= 0; }));
}

Box3 TubeTree::bounds() const
{
  Box3 box;
  for (std::size_t i = 0; i < points.size(); ++i)
  {
    box.extend(points[i] - vec3(radii[i]));
    box.extend(points[i] + vec3(radii[i]));
  }
  return box;
}

void TubeTree::append(const TubeTree& other, const glm::mat4& transform, std::uint32_t color)
{
  const std::int64_t offset = std::int64_t(points.size());
  for (std::size_t i = 0; i < other.size(); ++i)
  {
    points.push_back(vec3(transform * vec4(other.points[i], 1.0f)));
    radii.push_back(other.radii[i]);
    predecessors.push_back(other.predecessors[i] < 0 ? -1 : other.predecessors[i] + offset);
    colors.push_back(color);
  }
}

namespace
{
vec3 randomUnit(std::mt19937& rng)
{
  std::normal_distribution<float> n;
  vec3 v;
  do
    v = vec3(n(rng), n(rng), n(rng));
  while (glm::dot(v, v) < 1e-6f);
  return glm::normalize(v);
}

std::uint32_t randomColor(std::mt19937& rng)
{
  // Saturated but light colours, so shading stays readable.
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  const float h = 6.0f * u(rng);
  const float x = 1.0f - std::abs(std::fmod(h, 2.0f) - 1.0f);
  vec3 c = h < 1 ? vec3(1, x, 0) : h < 2 ? vec3(x, 1, 0) : h < 3 ? vec3(0, 1, x)
    : h < 4 ? vec3(0, x, 1) : h < 5 ? vec3(x, 0, 1) : vec3(1, 0, x);
  c = 0.35f + 0.65f * c;
  return packRGBA8(std::uint8_t(255 * c.r), std::uint8_t(255 * c.g), std::uint8_t(255 * c.b));
}
} // namespace

TubeTree syntheticNeuron(std::size_t links, unsigned seed)
{
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  TubeTree t;
  t.points.push_back(vec3(0.0f));
  t.radii.push_back(8.0f); // soma
  t.predecessors.push_back(-1);
  struct Tip
  {
    std::int64_t point;
    vec3 direction;
    float radius;
    float taper; ///< radius lost per step
  };
  std::vector<Tip> tips;
  for (int d = 0; d < 6; ++d)
    tips.push_back({ 0, randomUnit(rng), 1.5f, 0.004f });
  tips.push_back({ 0, vec3(0, -1, 0), 0.8f, 0.0005f }); // the axon: long, thin, straight-ish
  const float somaRadius = t.radii[0];
  while (t.points.size() <= links && !tips.empty())
  {
    // Grow a random tip by one step.
    const std::size_t k = std::size_t(rng() % tips.size());
    Tip& tip = tips[k];
    const bool axon = tip.taper < 0.001f;
    tip.direction = glm::normalize(tip.direction + (axon ? 0.15f : 0.45f) * randomUnit(rng));
    const vec3 from = t.points[std::size_t(tip.point)];
    // Primary branches start on the soma's surface rather than inside it.
    const float step = tip.point == 0 ? somaRadius : 2.0f + 2.0f * u(rng);
    t.points.push_back(from + step * tip.direction);
    tip.radius = std::max(0.25f, tip.radius - tip.taper * step);
    t.radii.push_back(tip.radius);
    t.predecessors.push_back(tip.point);
    tip.point = std::int64_t(t.points.size() - 1);
    if (!axon && u(rng) < 0.035f && tips.size() < 200)
    {
      // Bifurcation: two children thinner by Rall's law, r^1.5 = r1^1.5 + r2^1.5.
      const float child = tip.radius * std::pow(0.5f, 2.0f / 3.0f);
      tip.radius = child;
      Tip other = tip;
      other.direction = glm::normalize(tip.direction + 0.9f * randomUnit(rng));
      tips.push_back(other);
    }
    else if (!axon && tip.radius <= 0.25f && u(rng) < 0.02f)
      tips.erase(tips.begin() + std::ptrdiff_t(k)); // a terminal
  }
  return t;
}

TubeTree neuronAssembly(const TubeTree& base, std::size_t copies, float spacing, unsigned seed)
{
  if (base.size() * copies >= std::size_t(INT32_MAX))
    throw std::invalid_argument("sightline::neuronAssembly: " + std::to_string(copies) +
      " copies of " + std::to_string(base.size()) + " points exceed 2^31 - 1 points");
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  const float edge = spacing * std::cbrt(float(copies));
  TubeTree out;
  out.points.reserve(base.size() * copies);
  out.radii.reserve(base.size() * copies);
  out.predecessors.reserve(base.size() * copies);
  out.colors.reserve(base.size() * copies);
  for (std::size_t c = 0; c < copies; ++c)
  {
    const vec3 position = edge * vec3(u(rng), u(rng), u(rng));
    glm::mat4 transform = glm::translate(glm::mat4(1.0f), position);
    transform = glm::rotate(transform, 6.2831853f * u(rng), randomUnit(rng));
    out.append(base, transform, randomColor(rng));
  }
  return out;
}

TubeTree syntheticStreamlines(std::size_t lines, std::size_t linksPerLine, float edge,
  float radius, unsigned seed)
{
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  TubeTree t;
  const std::size_t total = lines * (linksPerLine + 1);
  t.points.reserve(total);
  t.radii.reserve(total);
  t.predecessors.reserve(total);
  t.colors.reserve(total);
  for (std::size_t l = 0; l < lines; ++l)
  {
    // A direction that turns slowly (a sum of two sinusoids per axis), unit steps.
    vec3 p = edge * vec3(u(rng), u(rng), u(rng));
    const vec3 heading = randomUnit(rng);
    vec3 phase = 6.2831853f * vec3(u(rng), u(rng), u(rng));
    const float wavelength = 20.0f + 40.0f * u(rng);
    const float radiusPhase = 6.2831853f * u(rng);
    const std::uint32_t color = randomColor(rng);
    for (std::size_t k = 0; k <= linksPerLine; ++k)
    {
      const float s = float(k) / wavelength * 6.2831853f;
      const vec3 direction = glm::normalize(heading + 0.7f * vec3(std::sin(s + phase.x),
        std::sin(0.7f * s + phase.y), std::sin(1.3f * s + phase.z)));
      t.points.push_back(p);
      t.radii.push_back(radius * (1.0f + 0.4f * std::sin(0.5f * s + radiusPhase)));
      t.predecessors.push_back(k == 0 ? -1 : std::int64_t(t.points.size()) - 2);
      t.colors.push_back(color);
      p += direction;
    }
  }
  return t;
}
} // namespace sightline
