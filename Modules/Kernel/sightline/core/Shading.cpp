// SPDX-License-Identifier: BSD-3-Clause
#include "sightline/core/Shading.h"

#include <algorithm>
#include <cmath>

namespace sightline
{
Lighting Lighting::headlight(const vec3& viewDirection)
{
  Lighting lighting;
  lighting.lights.push_back({ glm::normalize(viewDirection), vec3(1.0f), 1.0f });
  return lighting;
}

namespace
{
constexpr float kPi = kPiOf<float>;

vec3 shadeGltf(const Material& m, const vec3& ambientColor, const vec3& baseColor,
  const vec3& normal, const vec3& toViewer, const Lighting& lighting, const float* visibility)
{
  const float alpha = std::max(m.roughness * m.roughness, 1e-4f);
  const float alpha2 = alpha * alpha;
  const float NdotV = std::max(glm::dot(normal, toViewer), 1e-4f);
  vec3 reflected(0.0f);
  for (std::size_t i = 0; i < lighting.lights.size(); ++i)
  {
    const DirectionalLight& light = lighting.lights[i];
    const vec3 toLight = -light.direction;
    const float NdotL = glm::dot(normal, toLight);
    if (NdotL <= 0.0f || (visibility && visibility[i] <= 0.0f))
      continue;
    const vec3 halfway = glm::normalize(toLight + toViewer);
    const float NdotH = std::max(glm::dot(normal, halfway), 0.0f);
    const float VdotH = std::max(glm::dot(toViewer, halfway), 0.0f);
    const float denominator = NdotH * NdotH * (alpha2 - 1.0f) + 1.0f;
    const float D = alpha2 / (kPi * denominator * denominator);
    const float V = 0.5f /
      (NdotL * std::sqrt(NdotV * NdotV * (1.0f - alpha2) + alpha2) +
        NdotV * std::sqrt(NdotL * NdotL * (1.0f - alpha2) + alpha2));
    const float F = 0.04f + 0.96f * std::pow(1.0f - VdotH, 5.0f);
    // Irradiance pi * intensity: a white Lambertian surface facing the light reflects 1.
    const vec3 irradiance = light.color * (light.intensity * kPi * NdotL) * (visibility ? visibility[i] : 1.0f);
    reflected += irradiance * (m.diffuse * (1.0f - F) * baseColor / kPi + m.specular * vec3(F * D * V));
  }
  return m.ambient * ambientColor + reflected;
}
} // namespace

vec3 shade(const Material& m, const vec3& ambientColor, const vec3& diffuseColor,
  const vec3& normal, const vec3& toViewer, const Lighting& lighting, const float* visibility)
{
  if (m.model == ShadingModel::GltfDielectric)
    return shadeGltf(m, ambientColor, diffuseColor, normal, toViewer, lighting, visibility);
  vec3 diffuse(0.0f);
  vec3 specular(0.0f);
  for (std::size_t i = 0; i < lighting.lights.size(); ++i)
  {
    const DirectionalLight& light = lighting.lights[i];
    const vec3 toLight = -light.direction;
    const float lambert = glm::dot(normal, toLight);
    if (lambert <= 0.0f)
      continue;
    const vec3 radiance = light.color * light.intensity * (visibility ? visibility[i] : 1.0f);
    diffuse += radiance * lambert;
    if (m.specular > 0.0f)
    {
      const vec3 halfway = glm::normalize(toLight + toViewer);
      specular += radiance * std::pow(std::max(glm::dot(normal, halfway), 0.0f), m.specularPower);
    }
  }
  return m.ambient * ambientColor + m.diffuse * diffuseColor * diffuse +
    m.specular * m.specularColor * specular;
}
} // namespace sightline
