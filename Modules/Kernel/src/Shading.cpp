#include "sightline/Shading.h"

#include <cmath>

namespace sightline
{
Lighting Lighting::headlight(const vec3& viewDirection)
{
  Lighting lighting;
  lighting.lights.push_back({ glm::normalize(viewDirection), vec3(1.0f), 1.0f });
  return lighting;
}

vec3 shade(const Material& m, const vec3& ambientColor, const vec3& diffuseColor,
  const vec3& normal, const vec3& toViewer, const Lighting& lighting)
{
  vec3 diffuse(0.0f);
  vec3 specular(0.0f);
  for (const DirectionalLight& light : lighting.lights)
  {
    const vec3 toLight = -light.direction;
    const float lambert = glm::dot(normal, toLight);
    if (lambert <= 0.0f)
      continue;
    const vec3 radiance = light.color * light.intensity;
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
