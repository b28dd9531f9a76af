// Local shading shared by every primitive: ambient + Lambert + Blinn-Phong specular with
// VTK's vtkProperty parameters, under directional lights.
#pragma once

#include "sightline/Math.h"

#include <vector>

namespace sightline
{
/// Surface appearance with vtkProperty's meaning and defaults.
struct Material
{
  vec3 color{ 1.0f };         ///< diffuse colour when a primitive has no colour of its own
  vec3 ambientColor{ 1.0f };  ///< used when the primitive has no colour of its own
  vec3 specularColor{ 1.0f };
  float ambient = 0.0f;
  float diffuse = 1.0f;
  float specular = 0.0f;
  float specularPower = 1.0f;
  float opacity = 1.0f;
};

/// A light at infinity. `direction` is the way the light travels (from the light to the scene),
/// as vtkLight's focal point minus position.
struct DirectionalLight
{
  vec3 direction{ 0.0f, 0.0f, -1.0f };
  vec3 color{ 1.0f };
  float intensity = 1.0f;
};

struct Lighting
{
  std::vector<DirectionalLight> lights;

  /// VTK's default: one white headlight shining along the view direction.
  static Lighting headlight(const vec3& viewDirection);
};

/// Colour of a surface point. `normal` must be unit length and face the viewer;
/// `toViewer` is the unit vector from the point to the eye. A primitive's own colour replaces
/// the material's ambient and diffuse colours, as VTK does for scalar colouring.
vec3 shade(const Material& material, const vec3& ambientColor, const vec3& diffuseColor,
  const vec3& normal, const vec3& toViewer, const Lighting& lighting);
} // namespace sightline
