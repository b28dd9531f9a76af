// SPDX-License-Identifier: BSD-3-Clause
#include "SightlineKernelConversions.h"

#include "vtkAlgorithm.h"
#include "vtkCamera.h"
#include "vtkDataSet.h"
#include "vtkLight.h"
#include "vtkLightCollection.h"
#include "vtkMapper.h"
#include "vtkMatrix4x4.h"
#include "vtkProperty.h"
#include "vtkUnsignedCharArray.h"
#include "vtkVolumeProperty.h"

#include "sightline/core/Geometry.h"

#include <algorithm>
#include <limits>
#include <cmath>

namespace SightlineKernelConversions
{
//------------------------------------------------------------------------------
sightline::dmat4 ToKernelMatrix(vtkMatrix4x4* matrix)
{
  sightline::dmat4 g;
  for (int row = 0; row < 4; ++row)
  {
    for (int col = 0; col < 4; ++col)
    {
      g[col][row] = matrix->GetElement(row, col); // GLM is column-major
    }
  }
  return g;
}

//------------------------------------------------------------------------------
sightline::Lighting MakeLighting(vtkLightCollection* lights, vtkCamera* camera)
{
  double position[3], focal[3];
  camera->GetPosition(position);
  camera->GetFocalPoint(focal);
  const sightline::vec3 viewDirection(
    focal[0] - position[0], focal[1] - position[1], focal[2] - position[2]);
  if (!lights || lights->GetNumberOfItems() == 0)
  {
    return sightline::Lighting::headlight(viewDirection);
  }

  sightline::Lighting lighting;
  vtkCollectionSimpleIterator it;
  lights->InitTraversal(it);
  while (vtkLight* light = lights->GetNextLight(it))
  {
    if (!light->GetSwitch())
    {
      continue;
    }
    double from[3], to[3];
    if (light->LightTypeIsHeadlight())
    {
      std::copy(position, position + 3, from);
      std::copy(focal, focal + 3, to);
    }
    else if (light->LightTypeIsCameraLight())
    {
      // Camera lights are given in the camera's frame; VTK moves them with the camera.
      vtkMatrix4x4* m = camera->GetCameraLightTransformMatrix();
      double p[4] = { 0, 0, 0, 1 }, f[4] = { 0, 0, 0, 1 };
      light->GetPosition(p);
      light->GetFocalPoint(f);
      m->MultiplyPoint(p, p);
      m->MultiplyPoint(f, f);
      for (int i = 0; i < 3; ++i)
      {
        from[i] = p[i] / p[3];
        to[i] = f[i] / f[3];
      }
    }
    else
    {
      light->GetTransformedPosition(from);
      light->GetTransformedFocalPoint(to);
    }
    const sightline::vec3 direction(to[0] - from[0], to[1] - from[1], to[2] - from[2]);
    if (glm::length(direction) == 0.0f)
    {
      continue;
    }
    double color[3];
    light->GetDiffuseColor(color);
    lighting.lights.push_back({ glm::normalize(direction),
      sightline::vec3(color[0], color[1], color[2]), static_cast<float>(light->GetIntensity()) });
  }
  return lighting;
}

//------------------------------------------------------------------------------
bool HasPositionalLight(vtkLightCollection* lights)
{
  if (!lights)
  {
    return false;
  }
  vtkCollectionSimpleIterator it;
  lights->InitTraversal(it);
  while (vtkLight* light = lights->GetNextLight(it))
  {
    if (light->GetSwitch() && light->GetPositional())
    {
      return true;
    }
  }
  return false;
}

//------------------------------------------------------------------------------
sightline::Material MaterialFromProperty(vtkProperty* p)
{
  sightline::Material m;
  double c[3];
  p->GetDiffuseColor(c);
  m.color = sightline::vec3(c[0], c[1], c[2]);
  p->GetAmbientColor(c);
  m.ambientColor = sightline::vec3(c[0], c[1], c[2]);
  p->GetSpecularColor(c);
  m.specularColor = sightline::vec3(c[0], c[1], c[2]);
  m.ambient = static_cast<float>(p->GetAmbient());
  m.diffuse = static_cast<float>(p->GetDiffuse());
  m.specular = static_cast<float>(p->GetSpecular());
  m.specularPower = static_cast<float>(p->GetSpecularPower());
  if (p->GetInterpolation() == VTK_PBR)
  {
    m.model = sightline::ShadingModel::GltfDielectric;
    m.roughness = static_cast<float>(p->GetRoughness());
  }
  m.opacity = static_cast<float>(p->GetOpacity());
  return m;
}

//------------------------------------------------------------------------------
sightline::Material MaterialFromVolumeProperty(vtkVolumeProperty* property)
{
  sightline::Material material;
  material.ambient = static_cast<float>(property->GetAmbient(0));
  material.diffuse = static_cast<float>(property->GetDiffuse(0));
  material.specular = static_cast<float>(property->GetSpecular(0));
  material.specularPower = static_cast<float>(property->GetSpecularPower(0));
  return material;
}

namespace
{
// Mapped RGB(A) colours as packed RGBA8, or empty when they are not `count` colours.
std::vector<std::uint32_t> Packed(vtkUnsignedCharArray* mapped, vtkIdType count)
{
  std::vector<std::uint32_t> colors;
  const int components = mapped->GetNumberOfComponents();
  if (mapped->GetNumberOfTuples() != count || components < 3)
  {
    return colors;
  }
  colors.resize(static_cast<std::size_t>(count));
  for (vtkIdType i = 0; i < count; ++i)
  {
    const unsigned char* c = mapped->GetPointer(i * components);
    colors[i] = sightline::packRGBA8(c[0], c[1], c[2], components > 3 ? c[3] : 255);
  }
  return colors;
}
} // namespace

//------------------------------------------------------------------------------
std::vector<std::uint32_t> CellColors(vtkMapper* mapper, vtkDataSet* input)
{
  int cellFlag = 0;
  vtkUnsignedCharArray* mapped =
    mapper->GetScalarVisibility() ? mapper->MapScalars(input, 1.0, cellFlag) : nullptr;
  return mapped && cellFlag == 1 ? Packed(mapped, input->GetNumberOfCells())
                                 : std::vector<std::uint32_t>();
}

//------------------------------------------------------------------------------
PointOrCellColors ColorsByPointOrCell(vtkMapper* mapper, vtkDataSet* input)
{
  PointOrCellColors colors;
  bool cellScalars = false;
  colors.points = PointColors(mapper, input, &cellScalars);
  if (cellScalars)
  {
    colors.cells = CellColors(mapper, input);
  }
  return colors;
}

//------------------------------------------------------------------------------
std::vector<std::uint32_t> PointColors(vtkMapper* mapper, vtkDataSet* input, bool* cellScalars)
{
  std::vector<std::uint32_t> colors;
  if (cellScalars)
  {
    *cellScalars = false;
  }
  if (!mapper->GetScalarVisibility())
  {
    return colors;
  }
  int cellFlag = 0;
  vtkUnsignedCharArray* mapped = mapper->MapScalars(input, 1.0, cellFlag);
  if (!mapped)
  {
    return colors;
  }
  if (cellFlag)
  {
    if (cellScalars)
    {
      *cellScalars = true;
    }
    return colors;
  }
  return Packed(mapped, input->GetNumberOfPoints());
}

//------------------------------------------------------------------------------
void WarnAboutReport(vtkObject* reporter, const sightline::ValidationReport& report)
{
  for (const std::string& reason : report.reasons)
  {
    vtkWarningWithObjectMacro(reporter, << reason << ".");
  }
}

//------------------------------------------------------------------------------
std::function<bool(double)> ProgressCallback(vtkAlgorithm* algorithm)
{
  return [algorithm](double fraction)
  {
    algorithm->UpdateProgress(fraction);
    return !algorithm->GetAbortExecute();
  };
}
//------------------------------------------------------------------------------
sightline::dvec3 ToLocalFrame(
  const std::vector<sightline::dvec3>& world, std::vector<sightline::vec3>& local)
{
  sightline::dvec3 lower(std::numeric_limits<double>::infinity());
  sightline::dvec3 upper(-std::numeric_limits<double>::infinity());
  for (const sightline::dvec3& p : world)
  {
    if (std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z))
    {
      lower = glm::min(lower, p);
      upper = glm::max(upper, p);
    }
  }
  sightline::dvec3 origin(0.0);
  if (lower.x <= upper.x)
  {
    // The centre, rounded to a multiple of a power of two near 1/64 of the extent: as near the
    // centre as precision needs, and with few bits, so that the origin is a float and float16
    // files' positions keep exact float16 offsets (compact tube chunks, sightline::TubeSet).
    origin = 0.5 * lower + 0.5 * upper;
    const double extent = std::max({ upper.x - lower.x, upper.y - lower.y, upper.z - lower.z });
    if (extent > 0.0 && std::isfinite(extent))
    {
      const double step = std::exp2(std::floor(std::log2(extent / 64.0)));
      origin = step * glm::round(origin / step);
    }
  }
  local.resize(world.size());
  for (std::size_t i = 0; i < world.size(); ++i)
  {
    local[i] = sightline::vec3(world[i] - origin);
  }
  return origin;
}
bool ToKernelRegion(vtkObject* reporter, const double region[6], sightline::dvec3& lower, sightline::dvec3& upper)
{
  for (int axis = 0; axis < 3; ++axis)
  {
    if (!(region[2 * axis] <= region[2 * axis + 1]))
    {
      vtkErrorWithObjectMacro(reporter, << "The region's " << "xyz"[axis] << " range [" << region[2 * axis]
                                        << ", " << region[2 * axis + 1] << "] is empty or not a number.");
      return false;
    }
    lower[axis] = region[2 * axis];
    upper[axis] = region[2 * axis + 1];
  }
  return true;
}
} // namespace SightlineKernelConversions
