// SPDX-License-Identifier: BSD-3-Clause
// Local shading shared by every primitive: ambient + Lambert + Blinn-Phong specular with
// VTK's vtkProperty parameters, under directional lights.
#pragma once

#include "sightline/math/Math.h"

#include <vector>

namespace sightline
{
/// How light is reflected.
enum class ShadingModel
{
  Phong, ///< VTK's ambient + Lambert + Blinn-Phong with vtkProperty's parameters
  /// glTF 2.0's dielectric metallic-roughness BRDF (GGX, height-correlated Smith, Schlick
  /// Fresnel with F0 = 0.04) plus constant ambient: what Peters et al. use for SH glyphs.
  GltfDielectric,
};

/// Surface appearance with vtkProperty's meaning and defaults.
struct Material
{
  ShadingModel model = ShadingModel::Phong;
  float roughness = 0.45f; ///< perceptual roughness of the glTF model
  // In the glTF model `ambient` is the constant ambient term, `diffuse` and `specular` weight
  // the BRDF's two lobes (1 and 1 for the physically based result).
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
/// `lightVisibility`, when given, holds one factor in [0, 1] per light (its unshadowed part).
/// In the glTF model a light of intensity 1 has irradiance pi, so a white surface facing it
/// reflects (1 - F0) = 0.96 of VTK's Lambert value through the diffuse lobe, plus the specular
/// lobe: the two models can be swapped without relighting the scene.
vec3 shade(const Material& material, const vec3& ambientColor, const vec3& diffuseColor,
  const vec3& normal, const vec3& toViewer, const Lighting& lighting,
  const float* lightVisibility = nullptr);
} // namespace sightline
