// SPDX-License-Identifier: BSD-3-Clause
#include "vtkSightlineGlyphMapper.h"

#include "SightlineKernelConversions.h"

#include "vtkCamera.h"
#include "vtkDataArray.h"
#include "vtkDataSet.h"
#include "vtkImageData.h"
#include "vtkMath.h"
#include "vtkMatrix3x3.h"
#include "vtkMatrix4x4.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkProp3D.h"
#include "vtkScalarsToColors.h"
#include "vtkUnsignedCharArray.h"

#include "sightline/glyphs/EllipsoidSet.h"
#include "sightline/glyphs/SHGlyphPreparation.h"
#include "sightline/glyphs/SHGlyphSet.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <exception>

vtkCxxSetObjectMacro(vtkSightlineGlyphMapper, DataToWorldMatrix, vtkMatrix4x4);
vtkCxxSetObjectMacro(vtkSightlineGlyphMapper, DirectionToWorldMatrix, vtkMatrix4x4);

namespace
{
/// The rotation closest to a linear map (polar decomposition by Newton's iteration), so that
/// voxel spacing or scaling in an sform does not distort the glyphs.
sightline::dmat3 ClosestRotation(sightline::dmat3 m)
{
  for (int i = 0; i < 30; ++i)
  {
    const sightline::dmat3 next = 0.5 * (m + glm::transpose(glm::inverse(m)));
    const sightline::dmat3 change = next - m;
    m = next;
    double largest = 0.0;
    for (int c = 0; c < 3; ++c)
      for (int r = 0; r < 3; ++r)
        largest = std::max(largest, std::abs(change[c][r]));
    if (largest < 1e-15)
      break;
  }
  return m;
}

/// Lookup table colours at 256 even steps, or the paper's black-red-yellow without a table.
std::vector<sightline::vec3> RadiusColormap(vtkScalarsToColors* table)
{
  std::vector<sightline::vec3> colormap(256);
  for (int k = 0; k < 256; ++k)
  {
    if (table)
    {
      const double* range = table->GetRange();
      double rgb[3];
      table->GetColor(range[0] + (range[1] - range[0]) * k / 255.0, rgb);
      colormap[k] = sightline::vec3(rgb[0], rgb[1], rgb[2]);
    }
    else
    {
      const float u = k / 255.0f;
      colormap[k] =
        sightline::vec3(std::min(1.0f, 2.0f * u), std::max(0.0f, 2.0f * u - 1.0f), 0.0f);
    }
  }
  return colormap;
}
} // namespace

class vtkSightlineGlyphMapper::vtkGlyphInternals
{
public:
  sightline::SHGlyphPreparation Glyphs;       ///< per-point boxes and amplitudes
  std::shared_ptr<sightline::Geometry> Drawn; ///< what the last build drew
  /// Input point id of each drawn glyph (the kernel's primitive order), for selection.
  std::vector<vtkIdType> PointIds;
  /// Point ids of the prepared glyphs `points` that a kernel set with `sourceIndex` kept.
  void KeepPointIds(
    const std::vector<std::size_t>& points, const std::vector<std::uint32_t>& sourceIndex)
  {
    this->PointIds.resize(sourceIndex.size());
    for (std::size_t i = 0; i < sourceIndex.size(); ++i)
    {
      this->PointIds[i] = static_cast<vtkIdType>(points[sourceIndex[i]]);
    }
  }
  /// Glyph colours from the point scalars (COLOR_BY_SCALARS); false when there are none.
  bool MapColors(vtkSightlineGlyphMapper* self, vtkDataSet* input,
    const std::vector<std::size_t>& points, std::vector<std::uint32_t>& colors);
  /// FrustumCulling: planes in the mapper's world coordinates (inward unit normals n and
  /// offsets d, n.x + d >= 0 inside). The view's frustum decides when to rebuild; a wider one
  /// (half again the view angle, the depth range doubled) decides which boxes a build computes,
  /// so that small camera moves do not each ask for a rebuild.
  using Frustum = std::array<std::array<double, 4>, 6>;
  bool HasFrustum = false;
  Frustum View;
  Frustum Build;
  /// The bounding spheres (centre, radius) of the glyphs the last build gave loose boxes.
  std::vector<std::array<double, 4>> LooseSpheres;
  static bool Inside(const Frustum& frustum, const double centre[3], double radius)
  {
    for (const auto& plane : frustum)
    {
      if (plane[0] * centre[0] + plane[1] * centre[1] + plane[2] * centre[2] + plane[3] < -radius)
      {
        return false;
      }
    }
    return true;
  }
  /// Centres of the glyphs in world coordinates.
  /// World centres of the glyphs at `points` relative to the returned origin (see
  /// SightlineKernelConversions::ToLocalFrame).
  sightline::dvec3 Centers(vtkSightlineGlyphMapper* self, vtkDataSet* input,
    const std::vector<std::size_t>& points, std::vector<sightline::vec3>& centers) const;
};

//------------------------------------------------------------------------------
vtkSightlineGlyphMapper::vtkSightlineGlyphMapper()
  : GlyphInternals(new vtkGlyphInternals)
{
}

//------------------------------------------------------------------------------
vtkSightlineGlyphMapper::~vtkSightlineGlyphMapper()
{
  this->SetMaskArrayName(nullptr);
  this->SetDataToWorldMatrix(nullptr);
  this->SetDirectionToWorldMatrix(nullptr);
}

//------------------------------------------------------------------------------
vtkMTimeType vtkSightlineGlyphMapper::GetMTime()
{
  vtkMTimeType time = this->Superclass::GetMTime();
  for (vtkMatrix4x4* matrix : { this->DataToWorldMatrix, this->DirectionToWorldMatrix })
  {
    if (matrix)
    {
      time = std::max(time, matrix->GetMTime());
    }
  }
  return time;
}

//------------------------------------------------------------------------------
const char* vtkSightlineGlyphMapper::GetNormalizationAsString()
{
  switch (this->Normalization)
  {
    case NORMALIZE_NONE:
      return "None";
    case NORMALIZE_COEFFICIENT_NORM:
      return "CoefficientNorm";
    case NORMALIZE_GLOBAL:
      return "Global";
    default:
      return "MaxAmplitude";
  }
}

//------------------------------------------------------------------------------
const char* vtkSightlineGlyphMapper::GetSliceOrientationAsString()
{
  switch (this->SliceOrientation)
  {
    case SLICE_CORONAL:
      return "Coronal";
    case SLICE_SAGITTAL:
      return "Sagittal";
    case SLICE_EXTENT:
      return "Extent";
    default:
      return "Axial";
  }
}

//------------------------------------------------------------------------------
const char* vtkSightlineGlyphMapper::GetColoringAsString()
{
  switch (this->Coloring)
  {
    case COLOR_BY_SCALARS:
      return "Scalars";
    case COLOR_SOLID:
      return "Solid";
    case COLOR_BY_RADIUS:
      return "Radius";
    default:
      return "Direction";
  }
}

//------------------------------------------------------------------------------
const char* vtkSightlineGlyphMapper::GetNegativeLobesAsString()
{
  switch (this->NegativeLobes)
  {
    case NEGATIVE_LOBES_COLOR:
      return "Color";
    case NEGATIVE_LOBES_HIDE:
      return "Hide";
    default:
      return "Show";
  }
}

//------------------------------------------------------------------------------
const char* vtkSightlineGlyphMapper::GetIntersectionMethodAsString()
{
  switch (this->IntersectionMethod)
  {
    case INTERSECT_MARCHING:
      return "Marching";
    case INTERSECT_INTERVAL:
      return "Interval";
    case INTERSECT_AFFINE:
      return "Affine";
    default:
      return "Exact";
  }
}

//------------------------------------------------------------------------------
int vtkSightlineGlyphMapper::GetSliceAxis()
{
  if (this->SliceOrientation == SLICE_EXTENT)
  {
    return -1;
  }
  if (this->GetNumberOfInputConnections(0) > 0 && !this->Static)
  {
    this->GetInputAlgorithm()->Update();
  }
  auto* image = vtkImageData::SafeDownCast(this->GetDrawnInput());
  if (!image)
  {
    return -1;
  }
  // Columns of (DataToWorld * Direction): the world direction of each voxel axis.
  double columns[3][3];
  vtkMatrix3x3* direction = image->GetDirectionMatrix();
  for (int axis = 0; axis < 3; ++axis)
  {
    for (int row = 0; row < 3; ++row)
    {
      double value = 0.0;
      for (int k = 0; k < 3; ++k)
      {
        const double toWorld = this->DataToWorldMatrix
          ? this->DataToWorldMatrix->GetElement(row, k)
          : (row == k ? 1.0 : 0.0);
        value += toWorld * direction->GetElement(k, axis);
      }
      columns[axis][row] = value;
    }
  }
  // Axial slices lie across world z, coronal across y, sagittal across x.
  const int worldAxis = this->SliceOrientation == SLICE_AXIAL ? 2
    : this->SliceOrientation == SLICE_CORONAL                 ? 1
                                                              : 0;
  int best = 2;
  double bestAlignment = -1.0;
  for (int axis = 0; axis < 3; ++axis)
  {
    const double length = vtkMath::Norm(columns[axis]);
    const double alignment = length > 0.0 ? std::abs(columns[axis][worldAxis]) / length : 0.0;
    if (alignment > bestAlignment)
    {
      bestAlignment = alignment;
      best = axis;
    }
  }
  return best;
}


//------------------------------------------------------------------------------
bool vtkSightlineGlyphMapper::SelectPoints(vtkDataSet* input, std::vector<std::size_t>& ids)
{
  const vtkIdType points = input->GetNumberOfPoints();
  auto* image = vtkImageData::SafeDownCast(input);
  if (image)
  {
    int whole[6];
    image->GetExtent(whole);
    int extent[6];
    std::copy(whole, whole + 6, extent);
    if (this->SliceOrientation == SLICE_EXTENT)
    {
      for (int axis = 0; axis < 3; ++axis)
      {
        extent[2 * axis] = std::max(whole[2 * axis], this->DisplayExtent[2 * axis]);
        extent[2 * axis + 1] = std::min(whole[2 * axis + 1], this->DisplayExtent[2 * axis + 1]);
      }
    }
    else
    {
      const int axis = this->GetSliceAxis();
      int slice = this->SliceNumber;
      if (slice < 0)
      {
        slice = (whole[2 * axis] + whole[2 * axis + 1]) / 2;
      }
      else if (slice < whole[2 * axis] || slice > whole[2 * axis + 1])
      {
        const int clamped = std::max(whole[2 * axis], std::min(slice, whole[2 * axis + 1]));
        vtkWarningMacro(<< "Slice " << slice << " is outside the image's extent ["
                        << whole[2 * axis] << ", " << whole[2 * axis + 1] << "] along axis "
                        << axis << "; showing slice " << clamped << ".");
        slice = clamped;
      }
      extent[2 * axis] = extent[2 * axis + 1] = slice;
    }
    if (extent[0] > extent[1] || extent[2] > extent[3] || extent[4] > extent[5])
    {
      vtkErrorMacro(<< "The display extent [" << this->DisplayExtent[0] << ", "
                    << this->DisplayExtent[1] << ", " << this->DisplayExtent[2] << ", "
                    << this->DisplayExtent[3] << ", " << this->DisplayExtent[4] << ", "
                    << this->DisplayExtent[5] << "] does not overlap the image's extent ["
                    << whole[0] << ", " << whole[1] << ", " << whole[2] << ", " << whole[3]
                    << ", " << whole[4] << ", " << whole[5] << "]; nothing to render.");
      return false;
    }
    std::copy(extent, extent + 6, this->DrawnExtent);
    for (int k = extent[4]; k <= extent[5]; ++k)
    {
      for (int j = extent[2]; j <= extent[3]; ++j)
      {
        for (int i = extent[0]; i <= extent[1]; ++i)
        {
          int ijk[3] = { i, j, k };
          ids.push_back(static_cast<std::size_t>(image->ComputePointId(ijk)));
        }
      }
    }
  }
  else
  {
    ids.resize(points);
    for (vtkIdType i = 0; i < points; ++i)
    {
      ids[i] = static_cast<std::size_t>(i);
    }
  }

  if (this->MaskArrayName && *this->MaskArrayName)
  {
    vtkDataArray* mask = input->GetPointData()->GetArray(this->MaskArrayName);
    if (this->CheckPointArray(mask, "mask array '" + std::string(this->MaskArrayName) + "'",
          points, 1, "drawing without a mask"))
    {
      ids.erase(std::remove_if(ids.begin(), ids.end(),
                  [mask](std::size_t id)
                  { return mask->GetComponent(static_cast<vtkIdType>(id), 0) == 0.0; }),
        ids.end());
    }
  }
  return true;
}

//------------------------------------------------------------------------------
double vtkSightlineGlyphMapper::ComputeWorldScale(vtkDataSet* input)
{
  double worldScale = this->ScaleFactor;
  auto* image = vtkImageData::SafeDownCast(input);
  if (!image)
  {
    return worldScale;
  }
  double smallest = VTK_DOUBLE_MAX;
  int dims[3];
  image->GetDimensions(dims);
  double origin[3];
  image->TransformIndexToPhysicalPoint(0, 0, 0, origin);
  for (int axis = 0; axis < 3; ++axis)
  {
    int next[3] = { 0, 0, 0 };
    next[axis] = 1;
    double p[3];
    image->TransformIndexToPhysicalPoint(next[0], next[1], next[2], p);
    double a[4] = { origin[0], origin[1], origin[2], 1.0 }, b[4] = { p[0], p[1], p[2], 1.0 };
    if (this->DataToWorldMatrix)
    {
      this->DataToWorldMatrix->MultiplyPoint(a, a);
      this->DataToWorldMatrix->MultiplyPoint(b, b);
    }
    const double step = std::sqrt(vtkMath::Distance2BetweenPoints(a, b));
    if (step > 0.0 && (dims[axis] > 1 || smallest == VTK_DOUBLE_MAX))
    {
      smallest = std::min(smallest, step);
    }
  }
  if (smallest < VTK_DOUBLE_MAX)
  {
    worldScale *= 0.5 * smallest;
  }
  return worldScale;
}

//------------------------------------------------------------------------------
std::shared_ptr<sightline::Geometry> vtkSightlineGlyphMapper::BuildGeometry()
{
  vtkGlyphInternals& in = *this->GlyphInternals;
  in.Drawn.reset();
  in.PointIds.clear();
  this->LastComputedBoxes = 0;
  this->LastLooseBoxes = 0;
  std::fill(this->DrawnExtent, this->DrawnExtent + 6, 0);
  this->DrawnExtent[1] = this->DrawnExtent[3] = this->DrawnExtent[5] = -1;

  // Called only with points to draw (an empty input draws nothing, quietly).
  vtkDataSet* input = this->GetDrawnInput();
  const vtkIdType points = input ? input->GetNumberOfPoints() : 0;
  if (points == 0)
  {
    return nullptr;
  }
  if (!(std::isfinite(this->ScaleFactor) && this->ScaleFactor > 0.0))
  {
    vtkErrorMacro(<< "ScaleFactor must be positive and finite, got " << this->ScaleFactor
                  << "; no glyphs rendered.");
    return nullptr;
  }

  sightline::GlyphRequest request;
  // Directions given in other axes than the world's are turned into world axes.
  if (this->DirectionToWorldMatrix)
  {
    sightline::dmat3 linear;
    for (int c = 0; c < 3; ++c)
    {
      for (int r = 0; r < 3; ++r)
      {
        linear[c][r] = this->DirectionToWorldMatrix->GetElement(r, c); // GLM is column-major
      }
    }
    const double determinant = glm::determinant(linear);
    if (!(std::abs(determinant) > 1e-12) || !std::isfinite(determinant))
    {
      vtkErrorMacro(<< "DirectionToWorldMatrix is singular or not finite; no glyphs rendered.");
      return nullptr;
    }
    request.rotation = ClosestRotation(linear);
  }
  if (!this->SelectPoints(input, request.points))
  {
    return nullptr;
  }
  switch (this->Normalization)
  {
    case NORMALIZE_NONE:
      request.normalization = sightline::GlyphNormalization::None;
      break;
    case NORMALIZE_COEFFICIENT_NORM:
      request.normalization = sightline::GlyphNormalization::CoefficientNorm;
      break;
    case NORMALIZE_GLOBAL:
      request.normalization = sightline::GlyphNormalization::Global;
      break;
    default:
      request.normalization = sightline::GlyphNormalization::MaxAmplitude;
      break;
  }
  this->WorldScale = this->ComputeWorldScale(input);
  request.worldScale = this->WorldScale;
  request.maxAmplitudes =
    this->Coloring == COLOR_BY_RADIUS && !(this->RadiusRange[0] < this->RadiusRange[1]);
  request.progress = [this](double progress) { this->UpdateProgress(progress); };
  in.LooseSpheres.clear();
  if (this->FrustumCulling)
  {
    request.mayBeVisible = [this, input, &in](std::size_t point, double radius)
    {
      double centre[4] = { 0.0, 0.0, 0.0, 1.0 };
      input->GetPoint(static_cast<vtkIdType>(point), centre);
      if (this->DataToWorldMatrix)
      {
        this->DataToWorldMatrix->MultiplyPoint(centre, centre);
      }
      if (in.HasFrustum && vtkGlyphInternals::Inside(in.Build, centre, radius))
      {
        return true;
      }
      in.LooseSpheres.push_back({ centre[0], centre[1], centre[2], radius });
      return false;
    };
  }

  try
  {
    in.Drawn = this->BuildGlyphs(input, request);
  }
  catch (const std::exception& e)
  {
    vtkErrorMacro(<< "Could not build the glyphs: " << e.what());
    in.Drawn.reset();
  }
  return in.Drawn;
}

//------------------------------------------------------------------------------
int vtkSightlineGlyphMapper::ApplyMaximumOrder(int order)
{
  if (this->MaximumOrder < 0)
  {
    return order;
  }
  if (this->MaximumOrder % 2 != 0)
  {
    vtkWarningMacro(<< "MaximumOrder " << this->MaximumOrder
                    << " is odd; SH glyphs have even bands only, using "
                    << this->MaximumOrder - 1 << ".");
  }
  return std::min(order, this->MaximumOrder - this->MaximumOrder % 2);
}

//------------------------------------------------------------------------------
sightline::SHGlyphPreparation& vtkSightlineGlyphMapper::GetGlyphPreparation()
{
  return this->GlyphInternals->Glyphs;
}

//------------------------------------------------------------------------------
sightline::PreparedSHGlyphs vtkSightlineGlyphMapper::PrepareSHGlyphs(
  sightline::SHGlyphPreparation& preparation, const sightline::GlyphSource& source,
  const sightline::GlyphRequest& request, const std::string& label)
{
  sightline::PreparedSHGlyphs glyphs = preparation.prepare(source, request);
  this->ReportDroppedGlyphs(glyphs.drops, label);
  this->LastComputedBoxes += static_cast<vtkIdType>(glyphs.computedBoxes);
  this->LastLooseBoxes += static_cast<vtkIdType>(glyphs.looseBoxCount);
  return glyphs;
}

//------------------------------------------------------------------------------
void vtkSightlineGlyphMapper::SetView(vtkProp3D* prop, vtkCamera* camera, double aspect, bool interactive)
{
  vtkGlyphInternals& in = *this->GlyphInternals;
  in.HasFrustum = false;
  if (!this->FrustumCulling || !camera || !(aspect > 0.0) || !std::isfinite(aspect))
  {
    return;
  }
  // The camera's planes are in VTK's world coordinates; the glyphs are in the prop's: with
  // x_world = M x_prop, the plane p (as a row) becomes p M.
  vtkMatrix4x4* matrix = prop ? prop->GetMatrix() : nullptr;
  auto planesOf = [&](vtkCamera* view, vtkGlyphInternals::Frustum& frustum)
  {
    double world[24];
    view->GetFrustumPlanes(aspect, world);
    for (int i = 0; i < 6; ++i)
    {
      double plane[4];
      for (int c = 0; c < 4; ++c)
      {
        plane[c] = 0.0;
        for (int r = 0; r < 4; ++r)
        {
          plane[c] += world[4 * i + r] * (matrix ? matrix->GetElement(r, c) : (r == c ? 1.0 : 0.0));
        }
      }
      const double length = std::sqrt(plane[0] * plane[0] + plane[1] * plane[1] + plane[2] * plane[2]);
      if (!(length > 0.0) || !std::isfinite(length))
      {
        return false; // a degenerate camera or prop matrix: no culling
      }
      for (int c = 0; c < 4; ++c)
      {
        frustum[i][c] = plane[c] / length;
      }
    }
    return true;
  };
  vtkNew<vtkCamera> wide;
  wide->DeepCopy(camera);
  wide->SetViewAngle(std::min(170.0, 1.5 * camera->GetViewAngle()));
  wide->SetParallelScale(1.5 * camera->GetParallelScale());
  const double* range = camera->GetClippingRange();
  wide->SetClippingRange(0.5 * range[0], 2.0 * range[1]);
  if (!planesOf(camera, in.View) || !planesOf(wide, in.Build))
  {
    return;
  }
  in.HasFrustum = true;
  if (interactive)
  {
    return;
  }
  for (const auto& sphere : in.LooseSpheres)
  {
    if (vtkGlyphInternals::Inside(in.View, sphere.data(), sphere[3]))
    {
      this->Modified(); // rebuild with the near-exact boxes of what is now in view
      return;
    }
  }
}

//------------------------------------------------------------------------------
void vtkSightlineGlyphMapper::ReportDroppedGlyphs(
  const sightline::GlyphDrops& drops, const std::string& label)
{
  if (drops.nonFinite > 0)
  {
    vtkWarningMacro(<< drops.nonFinite << " glyph(s) have NaN or infinite values in the "
                    << label << " (the first at point " << drops.firstNonFinite
                    << "); they are not drawn.");
  }
}

//------------------------------------------------------------------------------
sightline::dvec3 vtkSightlineGlyphMapper::vtkGlyphInternals::Centers(vtkSightlineGlyphMapper* self,
  vtkDataSet* input, const std::vector<std::size_t>& points,
  std::vector<sightline::vec3>& centers) const
{
  std::vector<sightline::dvec3> world(points.size());
  for (std::size_t g = 0; g < points.size(); ++g)
  {
    double p[4] = { 0.0, 0.0, 0.0, 1.0 };
    input->GetPoint(static_cast<vtkIdType>(points[g]), p);
    if (self->DataToWorldMatrix)
    {
      self->DataToWorldMatrix->MultiplyPoint(p, p);
    }
    world[g] = sightline::dvec3(p[0], p[1], p[2]);
  }
  return SightlineKernelConversions::ToLocalFrame(world, centers);
}

//------------------------------------------------------------------------------
bool vtkSightlineGlyphMapper::vtkGlyphInternals::MapColors(vtkSightlineGlyphMapper* self,
  vtkDataSet* input, const std::vector<std::size_t>& points, std::vector<std::uint32_t>& colors)
{
  int cellFlag = 0;
  vtkUnsignedCharArray* mapped = self->MapScalars(input, 1.0, cellFlag);
  if (!mapped || cellFlag || mapped->GetNumberOfTuples() != input->GetNumberOfPoints() ||
    mapped->GetNumberOfComponents() < 3)
  {
    return false;
  }
  const int n = mapped->GetNumberOfComponents();
  colors.resize(points.size());
  for (std::size_t g = 0; g < points.size(); ++g)
  {
    const unsigned char* c = mapped->GetPointer(static_cast<vtkIdType>(points[g]) * n);
    colors[g] = sightline::packRGBA8(c[0], c[1], c[2], n > 3 ? c[3] : 255);
  }
  return true;
}

//------------------------------------------------------------------------------
void vtkSightlineGlyphMapper::ComputeSelectionIds(
  std::vector<vtkIdType>& pointIds, std::vector<vtkIdType>& vtkNotUsed(cellIds))
{
  const std::vector<vtkIdType>& kept = this->GlyphInternals->PointIds;
  std::copy_n(kept.begin(), std::min(kept.size(), pointIds.size()), pointIds.begin());
}

//------------------------------------------------------------------------------
std::shared_ptr<sightline::Geometry> vtkSightlineGlyphMapper::MakeSHGlyphSet(
  vtkDataSet* input, const sightline::PreparedSHGlyphs& glyphs, bool volume)
{
  vtkGlyphInternals& in = *this->GlyphInternals;
  if (glyphs.size() == 0)
  {
    if (!volume)
    {
      vtkWarningMacro(<< "Every selected glyph is zero, masked or invalid: nothing to render.");
    }
    return nullptr;
  }
  sightline::SHGlyphOptions options;
  std::vector<std::uint32_t> colors;
  if (volume)
  {
    options.coloring = sightline::SHColoring::Material;
  }
  else
  {
    options.coloring = this->Coloring == COLOR_SOLID ? sightline::SHColoring::Material
                                                     : sightline::SHColoring::Direction;
    if (this->Coloring == COLOR_BY_RADIUS)
    {
      // The paper's colour coding by scalar value: the lookup table over the radius range.
      double range[2] = { this->RadiusRange[0], this->RadiusRange[1] };
      if (!(range[0] < range[1]))
      {
        range[0] = 0.0;
        range[1] = 0.0;
        for (float amplitude : glyphs.maxAmplitudes)
        {
          range[1] = std::max(range[1], double(amplitude));
        }
        if (!(range[1] > 0.0))
        {
          range[1] = 1.0;
        }
      }
      std::copy(range, range + 2, this->LastRadiusRange);
      options.coloring = sightline::SHColoring::Radius;
      options.radiusRange = sightline::vec2(range[0], range[1]);
      options.colormap = RadiusColormap(this->LookupTable);
    }
    options.hideNegativeLobes = this->NegativeLobes == NEGATIVE_LOBES_HIDE;
    if (this->NegativeLobes == NEGATIVE_LOBES_COLOR)
    {
      options.negativeLobeColor = sightline::vec3(
        this->NegativeLobeColor[0], this->NegativeLobeColor[1], this->NegativeLobeColor[2]);
    }
    if (this->Coloring == COLOR_BY_SCALARS)
    {
      options.coloring = sightline::SHColoring::PerGlyph;
      if (!in.MapColors(this, input, glyphs.points, colors))
      {
        vtkWarningMacro(<< "Coloring by scalars needs point scalars to map (select them with "
                           "SetScalarModeToUsePointFieldData and SelectColorArray); using the "
                           "actor's colour.");
        options.coloring = sightline::SHColoring::Material;
      }
    }
    switch (this->IntersectionMethod)
    {
      case INTERSECT_MARCHING:
        options.method = sightline::SHIntersectionMethod::TensorMarching;
        break;
      case INTERSECT_INTERVAL:
      case INTERSECT_AFFINE:
        options.method = sightline::SHIntersectionMethod::IntervalSubdivision;
        break;
      default:
        break;
    }
    options.tensorMarching.stepSize = this->MarchingStepSize;
    options.tensorMarching.bisectionSteps = this->MarchingBisectionSteps;
    options.tensorMarching.linearInterpolation = this->MarchingLinearInterpolation;
    options.tensorMarching.centreStepFactor = this->MarchingCentreRefinement ? 1.0 / 3.0 : 1.0;
    options.subdivision.arithmetic = this->IntersectionMethod == INTERSECT_INTERVAL
      ? sightline::EnclosureArithmetic::Interval
      : sightline::EnclosureArithmetic::ReducedAffine;
    options.subdivision.tolerance = this->SubdivisionTolerance;
  }
  std::vector<sightline::vec3> centers;
  const sightline::dvec3 origin = in.Centers(this, input, glyphs.points, centers);
  auto set = std::make_shared<sightline::SHGlyphSet>(origin, centers, glyphs, options, colors);
  for (const std::string& reason : set->report().reasons)
  {
    vtkWarningMacro(<< (volume ? "Uncertainty glyphs: " : "") << reason << ".");
  }
  if (!volume)
  {
    in.KeepPointIds(glyphs.points, set->sourceIndex());
  }
  return set;
}

//------------------------------------------------------------------------------
std::shared_ptr<sightline::Geometry> vtkSightlineGlyphMapper::MakeEllipsoidSet(
  vtkDataSet* input, const sightline::PreparedEllipsoids& ellipsoids)
{
  vtkGlyphInternals& in = *this->GlyphInternals;
  if (ellipsoids.size() == 0)
  {
    vtkWarningMacro(<< "Every selected glyph is zero, masked or invalid: nothing to render.");
    return nullptr;
  }
  if (this->Coloring == COLOR_BY_RADIUS)
  {
    vtkWarningMacro(<< "Ellipsoids are coloured per glyph; colouring by direction instead of "
                       "by radius.");
  }
  std::vector<std::uint32_t> colors;
  if (this->Coloring == COLOR_BY_SCALARS && !in.MapColors(this, input, ellipsoids.points, colors))
  {
    vtkWarningMacro(<< "Coloring by scalars needs point scalars to map (select them with "
                       "SetScalarModeToUsePointFieldData and SelectColorArray); using the "
                       "actor's colour.");
  }
  else if (this->Coloring == COLOR_BY_DIRECTION || this->Coloring == COLOR_BY_RADIUS)
  {
    colors = ellipsoids.directionColors;
  }
  std::vector<sightline::vec3> centers;
  const sightline::dvec3 origin = in.Centers(this, input, ellipsoids.points, centers);
  auto set = std::make_shared<sightline::EllipsoidSet>(origin, centers, ellipsoids.axes, colors);
  for (const std::string& reason : set->report().reasons)
  {
    vtkWarningMacro(<< reason << ".");
  }
  in.KeepPointIds(ellipsoids.points, set->sourceIndex());
  return set;
}

//------------------------------------------------------------------------------
vtkIdType vtkSightlineGlyphMapper::GetMemoryBytes()
{
  const vtkGlyphInternals& in = *this->GlyphInternals;
  std::size_t bytes = in.Glyphs.memoryBytes();
  if (in.Drawn)
  {
    bytes += in.Drawn->memoryBytes();
  }
  return static_cast<vtkIdType>(bytes);
}

//------------------------------------------------------------------------------
void vtkSightlineGlyphMapper::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "MaximumOrder: " << this->MaximumOrder << "\n";
  os << indent << "Normalization: " << this->GetNormalizationAsString() << "\n";
  os << indent << "ScaleFactor: " << this->ScaleFactor << "\n";
  os << indent << "SliceOrientation: " << this->GetSliceOrientationAsString() << "\n";
  os << indent << "SliceNumber: " << this->SliceNumber << "\n";
  os << indent << "DisplayExtent: " << this->DisplayExtent[0] << " " << this->DisplayExtent[1]
     << " " << this->DisplayExtent[2] << " " << this->DisplayExtent[3] << " "
     << this->DisplayExtent[4] << " " << this->DisplayExtent[5] << "\n";
  os << indent << "DrawnExtent: " << this->DrawnExtent[0] << " " << this->DrawnExtent[1] << " "
     << this->DrawnExtent[2] << " " << this->DrawnExtent[3] << " " << this->DrawnExtent[4] << " "
     << this->DrawnExtent[5] << "\n";
  os << indent << "DataToWorldMatrix: " << (this->DataToWorldMatrix ? "set" : "(identity)") << "\n";
  os << indent << "DirectionToWorldMatrix: "
     << (this->DirectionToWorldMatrix ? "set" : "(world axes)") << "\n";
  os << indent << "MaskArrayName: " << (this->MaskArrayName ? this->MaskArrayName : "(none)")
     << "\n";
  os << indent << "Coloring: " << this->GetColoringAsString() << "\n";
  os << indent << "RadiusRange: " << this->RadiusRange[0] << " " << this->RadiusRange[1]
     << (this->RadiusRange[0] < this->RadiusRange[1] ? "" : " (automatic)") << "\n";
  os << indent << "LastRadiusRange: " << this->LastRadiusRange[0] << " "
     << this->LastRadiusRange[1] << "\n";
  os << indent << "NegativeLobes: " << this->GetNegativeLobesAsString() << "\n";
  os << indent << "NegativeLobeColor: " << this->NegativeLobeColor[0] << " "
     << this->NegativeLobeColor[1] << " " << this->NegativeLobeColor[2] << "\n";
  os << indent << "IntersectionMethod: " << this->GetIntersectionMethodAsString() << "\n";
  os << indent << "MarchingStepSize: " << this->MarchingStepSize << "\n";
  os << indent << "MarchingBisectionSteps: " << this->MarchingBisectionSteps << "\n";
  os << indent << "MarchingLinearInterpolation: " << this->MarchingLinearInterpolation << "\n";
  os << indent << "MarchingCentreRefinement: " << this->MarchingCentreRefinement << "\n";
  os << indent << "SubdivisionTolerance: " << this->SubdivisionTolerance << "\n";
  os << indent << "FrustumCulling: " << this->FrustumCulling << "\n";
  os << indent << "LastComputedBoxes: " << this->LastComputedBoxes << "\n";
  os << indent << "LastLooseBoxes: " << this->LastLooseBoxes << "\n";
  os << indent << "WorldScale: " << this->WorldScale << "\n";
}
