#include "vtkSightlineSHGlyphMapper.h"

#include "vtkDataArray.h"
#include "vtkDataSet.h"
#include "vtkImageData.h"
#include "vtkInformation.h"
#include "vtkMath.h"
#include "vtkMatrix3x3.h"
#include "vtkMatrix4x4.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkScalarsToColors.h"
#include "vtkUnsignedCharArray.h"

#include "sightline/core/EmbreeScene.h"
#include "sightline/core/Renderer.h"
#include "sightline/glyphs/SHGlyph.h"
#include "sightline/glyphs/SHGlyphSet.h"
#include "sightline/math/SHRotation.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <exception>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

vtkStandardNewMacro(vtkSightlineSHGlyphMapper);
vtkCxxSetObjectMacro(vtkSightlineSHGlyphMapper, DataToWorldMatrix, vtkMatrix4x4);
vtkCxxSetObjectMacro(vtkSightlineSHGlyphMapper, DirectionToWorldMatrix, vtkMatrix4x4);

namespace
{
constexpr float kNotComputed = std::numeric_limits<float>::quiet_NaN();

/// Values that depend only on one point's coefficients (not on the slice, the scale or the
/// normalisation), kept per input point while the array and the basis stay the same.
class PointCache
{
public:
  /// Boxes also depend on how the glyphs are turned (`rotation`, identity when they are not).
  bool Matches(vtkDataArray* array, int order, const sightline::SHConvention& convention,
    const glm::dmat3& rotation) const
  {
    return array == this->Array && array->GetMTime() == this->ArrayTime && order == this->Order &&
      convention.basis == this->Convention.basis && convention.legacy == this->Convention.legacy &&
      rotation == this->Rotation &&
      static_cast<std::size_t>(array->GetNumberOfTuples()) == this->HalfExtents.size();
  }

  void Reset(vtkDataArray* array, int order, const sightline::SHConvention& convention,
    const glm::dmat3& rotation)
  {
    this->Array = array;
    this->ArrayTime = array->GetMTime();
    this->Order = order;
    this->Convention = convention;
    this->Rotation = rotation;
    const std::size_t points = static_cast<std::size_t>(array->GetNumberOfTuples());
    this->HalfExtents.assign(points, sightline::vec3(kNotComputed));
    this->MaxAmplitude.assign(points, kNotComputed);
    this->GlobalMaxAmplitude = -1.0;
  }

  void Clear()
  {
    this->Array = nullptr;
    this->HalfExtents = {};
    this->MaxAmplitude = {};
  }

  std::size_t MemoryBytes() const
  {
    return this->HalfExtents.capacity() * sizeof(sightline::vec3) +
      this->MaxAmplitude.capacity() * sizeof(float);
  }

  /// Box half-extents of each point's unscaled glyph (NaN: not computed yet).
  std::vector<sightline::vec3> HalfExtents;
  /// max |F| of each point's glyph (NaN: not computed yet).
  std::vector<float> MaxAmplitude;
  /// Largest amplitude over every point of the array (negative: not computed yet).
  double GlobalMaxAmplitude = -1.0;

private:
  vtkDataArray* Array = nullptr;
  vtkMTimeType ArrayTime = 0;
  int Order = -1;
  sightline::SHConvention Convention;
  glm::dmat3 Rotation{ 1.0 };
};

/// The rotation closest to a linear map (polar decomposition by Newton's iteration), so that
/// voxel spacing or scaling in an sform does not distort the glyphs.
glm::dmat3 ClosestRotation(glm::dmat3 m)
{
  for (int i = 0; i < 30; ++i)
  {
    const glm::dmat3 next = 0.5 * (m + glm::transpose(glm::inverse(m)));
    const glm::dmat3 change = next - m;
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

std::string CountsOfOrders()
{
  std::ostringstream counts;
  for (int order = 0; order <= sightline::kMaxSHOrder; order += 2)
  {
    counts << (order ? ", " : "") << sightline::shCoefficientCount(order) << " (order " << order
           << ")";
  }
  return counts.str();
}
} // namespace

class vtkSightlineSHGlyphMapper::vtkGlyphInternals
{
public:
  PointCache Glyphs;
  PointCache Uncertainty;
  std::shared_ptr<sightline::SHGlyphSet> GlyphSet;
  std::shared_ptr<sightline::Geometry> Drawn; ///< what the last build drew (GlyphSet or another shape)
  std::shared_ptr<sightline::SHGlyphSet> UncertaintySet;
  std::unique_ptr<sightline::EmbreeScene> UncertaintyScene;
  double WorldScale = 1.0; ///< world length of a normalised glyph radius of 1
  bool WarnedSliceNumber = false;
};

//------------------------------------------------------------------------------
vtkSightlineSHGlyphMapper::vtkSightlineSHGlyphMapper()
  : GlyphInternals(new vtkGlyphInternals)
{
}

//------------------------------------------------------------------------------
vtkSightlineSHGlyphMapper::~vtkSightlineSHGlyphMapper()
{
  this->SetCoefficientArrayName(nullptr);
  this->SetMaskArrayName(nullptr);
  this->SetUncertaintyArrayName(nullptr);
  this->SetDataToWorldMatrix(nullptr);
  this->SetDirectionToWorldMatrix(nullptr);
}

//------------------------------------------------------------------------------
int vtkSightlineSHGlyphMapper::FillInputPortInformation(int vtkNotUsed(port), vtkInformation* info)
{
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkDataSet");
  return 1;
}

//------------------------------------------------------------------------------
vtkMTimeType vtkSightlineSHGlyphMapper::GetMTime()
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
bool vtkSightlineSHGlyphMapper::SetBasisByName(const char* name)
{
  try
  {
    const sightline::SHConvention convention =
      sightline::SHConvention::fromName(name ? name : "", this->LegacyBasis);
    this->SetBasis(convention.basis == sightline::SHBasis::Tournier07 ? TOURNIER07 : DESCOTEAUX07);
    return true;
  }
  catch (const std::exception& e)
  {
    vtkErrorMacro(<< "Unknown SH basis '" << (name ? name : "(null)") << "' (" << e.what()
                  << "); the basis stays " << this->GetBasisAsString() << ".");
    return false;
  }
}

//------------------------------------------------------------------------------
void vtkSightlineSHGlyphMapper::SetBasisToDIPY()
{
  this->SetBasis(DESCOTEAUX07);
  this->SetLegacyBasis(true);
}

//------------------------------------------------------------------------------
void vtkSightlineSHGlyphMapper::SetBasisToMRtrix3()
{
  this->SetBasis(TOURNIER07);
  this->SetLegacyBasis(false);
}

//------------------------------------------------------------------------------
const char* vtkSightlineSHGlyphMapper::GetBasisAsString()
{
  return this->Basis == TOURNIER07 ? "tournier07" : "descoteaux07";
}

//------------------------------------------------------------------------------
const char* vtkSightlineSHGlyphMapper::GetNormalizationAsString()
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
const char* vtkSightlineSHGlyphMapper::GetSliceOrientationAsString()
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
const char* vtkSightlineSHGlyphMapper::GetColoringAsString()
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
const char* vtkSightlineSHGlyphMapper::GetNegativeLobesAsString()
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
int vtkSightlineSHGlyphMapper::GetSliceAxis()
{
  if (this->SliceOrientation == SLICE_EXTENT)
  {
    return -1;
  }
  if (this->GetNumberOfInputConnections(0) > 0 && !this->Static)
  {
    this->GetInputAlgorithm()->Update();
  }
  auto* image = vtkImageData::SafeDownCast(this->GetInputDataObject(0, 0));
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
std::shared_ptr<sightline::Geometry> vtkSightlineSHGlyphMapper::BuildGeometry()
{
  vtkGlyphInternals& in = *this->GlyphInternals;
  in.GlyphSet.reset();
  in.Drawn.reset();
  in.UncertaintySet.reset();
  in.UncertaintyScene.reset();
  this->LastComputedBoxes = 0;
  std::fill(this->DrawnExtent, this->DrawnExtent + 6, 0);
  this->DrawnExtent[1] = this->DrawnExtent[3] = this->DrawnExtent[5] = -1;

  vtkDataSet* input = vtkDataSet::SafeDownCast(this->GetInputDataObject(0, 0));
  const vtkIdType points = input ? input->GetNumberOfPoints() : 0;
  if (points == 0)
  {
    vtkErrorMacro(<< "The input has no points: there are no glyphs to render.");
    return nullptr;
  }
  if (!(std::isfinite(this->ScaleFactor) && this->ScaleFactor > 0.0))
  {
    vtkErrorMacro(<< "ScaleFactor must be positive and finite, got " << this->ScaleFactor
                  << "; no glyphs rendered.");
    return nullptr;
  }

  // The coefficient array and the order its component count stands for.
  vtkPointData* pointData = input->GetPointData();
  int order = -1;
  bool canonicalInput = false;
  std::string arrayLabel;
  vtkDataArray* coefficients = this->SelectCoefficients(input, order, canonicalInput, arrayLabel);
  if (!coefficients)
  {
    return nullptr;
  }
  if (this->MaximumOrder >= 0)
  {
    if (this->MaximumOrder % 2 != 0)
    {
      vtkWarningMacro(<< "MaximumOrder " << this->MaximumOrder
                      << " is odd; SH glyphs have even bands only, using "
                      << this->MaximumOrder - 1 << ".");
    }
    order = std::min(order, this->MaximumOrder - this->MaximumOrder % 2);
  }
  const int stride = sightline::shCoefficientCount(order);
  const sightline::SHConvention convention = canonicalInput
    ? sightline::SHConvention{ sightline::SHBasis::Canonical, false }
    : sightline::SHConvention{ this->Basis == TOURNIER07 ? sightline::SHBasis::Tournier07
                                                         : sightline::SHBasis::Descoteaux07,
        this->LegacyBasis };

  // Directions given in other axes than the world's are turned into world axes.
  glm::dmat3 rotation(1.0);
  if (this->DirectionToWorldMatrix)
  {
    glm::dmat3 linear;
    for (int c = 0; c < 3; ++c)
    {
      for (int r = 0; r < 3; ++r)
      {
        linear[c][r] = this->DirectionToWorldMatrix->GetElement(r, c); // GLM is column-major
      }
    }
    if (!(std::abs(glm::determinant(linear)) > 1e-12) || !std::isfinite(glm::determinant(linear)))
    {
      vtkErrorMacro(<< "DirectionToWorldMatrix is singular or not finite; no glyphs rendered.");
      return nullptr;
    }
    rotation = ClosestRotation(linear);
  }
  const bool turned = rotation != glm::dmat3(1.0);

  // Which points: a slice or an extent of an image, every point of anything else.
  std::vector<vtkIdType> ids;
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
      return nullptr;
    }
    std::copy(extent, extent + 6, this->DrawnExtent);
    for (int k = extent[4]; k <= extent[5]; ++k)
    {
      for (int j = extent[2]; j <= extent[3]; ++j)
      {
        for (int i = extent[0]; i <= extent[1]; ++i)
        {
          int ijk[3] = { i, j, k };
          ids.push_back(image->ComputePointId(ijk));
        }
      }
    }
  }
  else
  {
    ids.resize(points);
    for (vtkIdType i = 0; i < points; ++i)
    {
      ids[i] = i;
    }
  }

  if (this->MaskArrayName && *this->MaskArrayName)
  {
    vtkDataArray* mask = pointData->GetArray(this->MaskArrayName);
    if (!mask)
    {
      vtkErrorMacro(<< "The mask array '" << this->MaskArrayName
                    << "' is not in the input's point data; drawing without a mask.");
    }
    else if (mask->GetNumberOfTuples() != points)
    {
      vtkErrorMacro(<< "The mask array '" << this->MaskArrayName << "' has "
                    << mask->GetNumberOfTuples() << " values for " << points
                    << " points; drawing without a mask.");
    }
    else
    {
      ids.erase(std::remove_if(ids.begin(), ids.end(),
                  [mask](vtkIdType id) { return mask->GetComponent(id, 0) == 0.0; }),
        ids.end());
    }
  }

  // Gather the drawn coefficients (the volume itself is never copied); skip non-finite ones.
  auto gather = [&](vtkDataArray* array, int count, const std::vector<vtkIdType>& which,
                  std::vector<float>& out)
  {
    out.resize(which.size() * count);
    std::vector<double> tuple(array->GetNumberOfComponents());
    for (std::size_t g = 0; g < which.size(); ++g)
    {
      array->GetTuple(which[g], tuple.data());
      std::copy(tuple.begin(), tuple.begin() + count, out.begin() + g * count);
    }
  };
  std::vector<float> values;
  gather(coefficients, stride, ids, values);
  {
    std::size_t kept = 0, badCount = 0;
    vtkIdType firstBad = -1;
    for (std::size_t g = 0; g < ids.size(); ++g)
    {
      const float* c = values.data() + g * stride;
      if (!std::all_of(c, c + stride, [](float v) { return std::isfinite(v); }))
      {
        if (badCount++ == 0)
        {
          firstBad = ids[g];
        }
        continue;
      }
      std::copy(c, c + stride, values.begin() + kept * stride);
      ids[kept++] = ids[g];
    }
    if (badCount > 0)
    {
      vtkWarningMacro(<< badCount << " glyph(s) have NaN or infinite values in the "
                      << arrayLabel << " (the first at point " << firstBad
                      << "); they are not drawn.");
    }
    ids.resize(kept);
    values.resize(kept * stride);
  }

  // Per-point caches of boxes and amplitudes, valid while the array and basis stay the same.
  if (!in.Glyphs.Matches(coefficients, order, convention, rotation))
  {
    in.Glyphs.Reset(coefficients, order, convention, rotation);
  }
  const int normalization = this->Normalization;
  std::vector<vtkIdType> needAmplitude;
  const bool radiusColors = this->Coloring == COLOR_BY_RADIUS;
  const bool automaticRadiusRange = !(this->RadiusRange[0] < this->RadiusRange[1]);
  if (normalization == NORMALIZE_MAX_AMPLITUDE || (radiusColors && automaticRadiusRange))
  {
    needAmplitude = ids;
  }
  if (normalization == NORMALIZE_GLOBAL && in.Glyphs.GlobalMaxAmplitude < 0.0)
  {
    // Every point of the input counts, so that all slices share one scale.
    needAmplitude.resize(points);
    for (vtkIdType i = 0; i < points; ++i)
    {
      needAmplitude[i] = i;
    }
  }
  std::vector<float> amplitudeValues;
  {
    std::vector<vtkIdType> missing;
    for (vtkIdType id : needAmplitude)
    {
      if (std::isnan(in.Glyphs.MaxAmplitude[id]))
      {
        missing.push_back(id);
      }
    }
    gather(coefficients, stride, missing, amplitudeValues);
    tbb::parallel_for(std::size_t(0), missing.size(),
      [&](std::size_t g)
      {
        const float* c = amplitudeValues.data() + g * stride;
        const bool finite = std::all_of(c, c + stride, [](float v) { return std::isfinite(v); });
        in.Glyphs.MaxAmplitude[missing[g]] =
          finite ? static_cast<float>(sightline::shMaxAmplitude(order, c, convention)) : 0.0f;
      });
    if (normalization == NORMALIZE_GLOBAL && in.Glyphs.GlobalMaxAmplitude < 0.0)
    {
      in.Glyphs.GlobalMaxAmplitude = 0.0;
      for (float amplitude : in.Glyphs.MaxAmplitude)
      {
        in.Glyphs.GlobalMaxAmplitude = std::max(in.Glyphs.GlobalMaxAmplitude, double(amplitude));
      }
    }
  }

  // World length of a normalised radius of 1: half the smallest voxel step for images.
  double worldScale = this->ScaleFactor;
  if (image)
  {
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
  }
  in.WorldScale = worldScale;

  // Per-glyph scale: the normalisation, then the world scale. Zero glyphs (background) drop.
  std::vector<float> scales;
  std::vector<vtkIdType> drawn;
  std::vector<float> drawnValues;
  scales.reserve(ids.size());
  for (std::size_t g = 0; g < ids.size(); ++g)
  {
    const float* c = values.data() + g * stride;
    if (std::all_of(c, c + stride, [](float v) { return v == 0.0f; }))
    {
      continue; // background voxels of a fit are all zero: normal, not an error
    }
    double divisor = 1.0;
    switch (normalization)
    {
      case NORMALIZE_MAX_AMPLITUDE:
        divisor = in.Glyphs.MaxAmplitude[ids[g]];
        break;
      case NORMALIZE_COEFFICIENT_NORM:
        divisor = sightline::shCoefficientNorm(order, c, convention);
        break;
      case NORMALIZE_GLOBAL:
        divisor = in.Glyphs.GlobalMaxAmplitude;
        break;
      default:
        break;
    }
    if (!(divisor > 0.0) || !std::isfinite(divisor))
    {
      continue; // nothing to draw at this size (e.g. only bands above MaximumOrder)
    }
    drawn.push_back(ids[g]);
    drawnValues.insert(drawnValues.end(), c, c + stride);
    scales.push_back(static_cast<float>(worldScale / divisor));
  }
  if (drawn.empty())
  {
    vtkWarningMacro(<< "Every selected glyph is zero, masked or invalid: nothing to render.");
    return nullptr;
  }

  // Turned glyphs: coefficients in the canonical basis, rotated (amplitudes and norms, cached
  // above from the input's coefficients, do not change under rotation).
  const sightline::SHConvention glyphConvention =
    turned ? sightline::SHConvention{ sightline::SHBasis::Canonical, false } : convention;
  auto turn = [&](int turnOrder, std::vector<float>& turnValues)
  {
    if (!turned)
    {
      return;
    }
    const int turnStride = sightline::shCoefficientCount(turnOrder);
    const sightline::SHConversion conversion =
      sightline::SHConversion::toCanonical(convention, turnOrder);
    const sightline::SHRotation turning(turnOrder, rotation);
    std::vector<double> canonical(turnStride), rotated(turnStride);
    for (std::size_t g = 0; g < turnValues.size() / turnStride; ++g)
    {
      float* c = turnValues.data() + g * turnStride;
      conversion.apply(c, canonical.data());
      turning.apply(canonical.data(), rotated.data());
      std::copy(rotated.begin(), rotated.end(), c);
    }
  };
  turn(order, drawnValues);

  // Boxes: cached per point, computed for the points that have none yet (with progress).
  auto computeBoxes = [&](PointCache& cache, int boxOrder, const std::vector<float>& boxValues)
  {
    const int boxStride = sightline::shCoefficientCount(boxOrder);
    std::vector<std::size_t> missing;
    for (std::size_t g = 0; g < drawn.size(); ++g)
    {
      if (std::isnan(cache.HalfExtents[drawn[g]].x))
      {
        missing.push_back(g);
      }
    }
    const sightline::SHConversion conversion =
      sightline::SHConversion::toCanonical(glyphConvention, boxOrder);
    const std::size_t block = 2048;
    for (std::size_t start = 0; start < missing.size(); start += block)
    {
      const std::size_t end = std::min(missing.size(), start + block);
      tbb::parallel_for(start, end,
        [&](std::size_t m)
        {
          const std::size_t g = missing[m];
          std::vector<double> canonical(boxStride);
          conversion.apply(boxValues.data() + g * boxStride, canonical.data());
          const int effective = sightline::shEffectiveOrder(boxOrder, canonical.data());
          cache.HalfExtents[drawn[g]] =
            sightline::vec3(sightline::shGlyphHalfExtents(effective, canonical.data()));
        });
      this->UpdateProgress(double(end) / double(missing.size()));
    }
    this->LastComputedBoxes += static_cast<vtkIdType>(missing.size());
    std::vector<sightline::vec3> halfExtents(drawn.size());
    for (std::size_t g = 0; g < drawn.size(); ++g)
    {
      halfExtents[g] = cache.HalfExtents[drawn[g]] * std::abs(scales[g]);
    }
    return halfExtents;
  };
  const std::vector<sightline::vec3> halfExtents = computeBoxes(in.Glyphs, order, drawnValues);

  // Centres in world coordinates.
  std::vector<sightline::vec3> centers(drawn.size());
  for (std::size_t g = 0; g < drawn.size(); ++g)
  {
    double p[4] = { 0.0, 0.0, 0.0, 1.0 };
    input->GetPoint(drawn[g], p);
    if (this->DataToWorldMatrix)
    {
      this->DataToWorldMatrix->MultiplyPoint(p, p);
    }
    centers[g] = sightline::vec3(p[0], p[1], p[2]);
  }

  sightline::SHGlyphOptions options;
  options.convention = glyphConvention;
  options.coloring = this->Coloring == COLOR_SOLID ? sightline::SHColoring::Material
                                                   : sightline::SHColoring::Direction;
  if (radiusColors)
  {
    // The paper's colour coding by scalar value: the lookup table over the radius range.
    double range[2] = { this->RadiusRange[0], this->RadiusRange[1] };
    if (automaticRadiusRange)
    {
      range[0] = 0.0;
      range[1] = 0.0;
      for (vtkIdType id : drawn)
      {
        range[1] = std::max(range[1], double(in.Glyphs.MaxAmplitude[id]));
      }
      if (!(range[1] > 0.0))
      {
        range[1] = 1.0;
      }
    }
    std::copy(range, range + 2, this->LastRadiusRange);
    options.coloring = sightline::SHColoring::Radius;
    options.radiusRange = sightline::vec2(range[0], range[1]);
    options.colormap.resize(256);
    if (this->LookupTable)
    {
      const double* table = this->LookupTable->GetRange();
      for (int k = 0; k < 256; ++k)
      {
        double rgb[3];
        this->LookupTable->GetColor(table[0] + (table[1] - table[0]) * k / 255.0, rgb);
        options.colormap[k] = sightline::vec3(rgb[0], rgb[1], rgb[2]);
      }
    }
    else
    {
      for (int k = 0; k < 256; ++k) // black - red - yellow
      {
        const float u = k / 255.0f;
        options.colormap[k] = sightline::vec3(std::min(1.0f, 2.0f * u), std::max(0.0f, 2.0f * u - 1.0f), 0.0f);
      }
    }
  }
  options.hideNegativeLobes = this->NegativeLobes == NEGATIVE_LOBES_HIDE;
  if (this->NegativeLobes == NEGATIVE_LOBES_COLOR)
  {
    options.negativeLobeColor = sightline::vec3(
      this->NegativeLobeColor[0], this->NegativeLobeColor[1], this->NegativeLobeColor[2]);
  }

  std::vector<std::uint32_t> colors;
  if (this->Coloring == COLOR_BY_SCALARS)
  {
    int cellFlag = 0;
    vtkUnsignedCharArray* mapped = this->MapScalars(input, 1.0, cellFlag);
    if (mapped && !cellFlag && mapped->GetNumberOfTuples() == points &&
      mapped->GetNumberOfComponents() >= 3)
    {
      const int n = mapped->GetNumberOfComponents();
      colors.resize(drawn.size());
      for (std::size_t g = 0; g < drawn.size(); ++g)
      {
        const unsigned char* c = mapped->GetPointer(drawn[g] * n);
        colors[g] = sightline::packRGBA8(c[0], c[1], c[2], n > 3 ? c[3] : 255);
      }
      options.coloring = sightline::SHColoring::PerGlyph;
    }
    else
    {
      vtkWarningMacro(<< "Coloring by scalars needs point scalars to map (select them with "
                         "SetScalarModeToUsePointFieldData and SelectColorArray); using the "
                         "actor's colour.");
      options.coloring = sightline::SHColoring::Material;
    }
  }

  std::shared_ptr<sightline::Geometry> geometry;
  try
  {
    geometry = this->CreateGlyphGeometry(centers, drawnValues, order, options, scales, colors, halfExtents);
    in.Drawn = geometry;

    // Uncertainty glyphs: the same centres and scale factors, drawn as a volume.
    if (this->UncertaintyArrayName && *this->UncertaintyArrayName)
    {
      vtkDataArray* uncertainty = pointData->GetArray(this->UncertaintyArrayName);
      const int uncertaintyOrder = uncertainty
        ? sightline::shOrderFromCount(static_cast<std::size_t>(uncertainty->GetNumberOfComponents()))
        : -1;
      if (!uncertainty)
      {
        vtkErrorMacro(<< "The uncertainty array '" << this->UncertaintyArrayName
                      << "' is not in the input's point data; drawing without uncertainty.");
      }
      else if (uncertaintyOrder < 0)
      {
        vtkErrorMacro(<< "The uncertainty array '" << this->UncertaintyArrayName << "' has "
                      << uncertainty->GetNumberOfComponents()
                      << " components, which is no SH order: expected one of "
                      << CountsOfOrders() << ". Drawing without uncertainty.");
      }
      else
      {
        if (!in.Uncertainty.Matches(uncertainty, uncertaintyOrder, convention, rotation))
        {
          in.Uncertainty.Reset(uncertainty, uncertaintyOrder, convention, rotation);
        }
        std::vector<float> uncertaintyValues;
        gather(uncertainty, sightline::shCoefficientCount(uncertaintyOrder), drawn,
          uncertaintyValues);
        turn(uncertaintyOrder, uncertaintyValues);
        const std::vector<sightline::vec3> uncertaintyBoxes =
          computeBoxes(in.Uncertainty, uncertaintyOrder, uncertaintyValues);
        sightline::SHGlyphOptions volumeOptions;
        volumeOptions.convention = glyphConvention;
        volumeOptions.coloring = sightline::SHColoring::Material;
        in.UncertaintySet = std::make_shared<sightline::SHGlyphSet>(centers, uncertaintyValues,
          uncertaintyOrder, volumeOptions, scales, std::vector<std::uint32_t>{}, uncertaintyBoxes);
        if (!in.UncertaintySet->report().reasons.empty())
        {
          vtkWarningMacro(<< "Uncertainty glyphs: " << in.UncertaintySet->report().reasons.front()
                          << ".");
        }
        if (in.UncertaintySet->size() > 0)
        {
          in.UncertaintyScene = std::make_unique<sightline::EmbreeScene>();
          in.UncertaintyScene->add(in.UncertaintySet);
          in.UncertaintyScene->commit();
        }
      }
    }
  }
  catch (const std::exception& e)
  {
    vtkErrorMacro(<< "Could not build the glyphs: " << e.what());
    in.GlyphSet.reset();
    in.Drawn.reset();
    in.UncertaintySet.reset();
    in.UncertaintyScene.reset();
    return nullptr;
  }
  return geometry;
}

//------------------------------------------------------------------------------
vtkDataArray* vtkSightlineSHGlyphMapper::SelectCoefficients(
  vtkDataSet* input, int& order, bool& canonical, std::string& label)
{
  canonical = false;
  vtkPointData* pointData = input->GetPointData();
  const bool named = this->CoefficientArrayName && *this->CoefficientArrayName;
  vtkDataArray* coefficients =
    named ? pointData->GetArray(this->CoefficientArrayName) : pointData->GetScalars();
  label = named ? "coefficient array '" + std::string(this->CoefficientArrayName) + "'"
                : std::string("active point scalars (the coefficient array)");
  if (!coefficients)
  {
    vtkErrorMacro(<< "The input has no " << label
                  << "; set CoefficientArrayName to the point-data array of SH coefficients.");
    return nullptr;
  }
  const int components = coefficients->GetNumberOfComponents();
  order = sightline::shOrderFromCount(static_cast<std::size_t>(components));
  if (order < 0)
  {
    vtkErrorMacro(<< "The " << label << " has " << components
                  << " components, which is no SH order: expected one of " << CountsOfOrders()
                  << ". (A 4-D NIfTI needs vtkNIFTIImageReader::TimeAsVectorOn().)");
    return nullptr;
  }
  return coefficients;
}

//------------------------------------------------------------------------------
std::shared_ptr<sightline::Geometry> vtkSightlineSHGlyphMapper::CreateGlyphGeometry(
  const std::vector<sightline::vec3>& centers, const std::vector<float>& values, int order,
  sightline::SHGlyphOptions& options, const std::vector<float>& scales,
  const std::vector<std::uint32_t>& colors, const std::vector<sightline::vec3>& halfExtents)
{
  vtkGlyphInternals& in = *this->GlyphInternals;
  in.GlyphSet = std::make_shared<sightline::SHGlyphSet>(
    centers, values, order, options, scales, colors, halfExtents);
  for (const std::string& reason : in.GlyphSet->report().reasons)
  {
    vtkWarningMacro(<< reason << ".");
  }
  return in.GlyphSet;
}

//------------------------------------------------------------------------------
void vtkSightlineSHGlyphMapper::ConfigureRender(sightline::RenderOptions& options)
{
  vtkGlyphInternals& in = *this->GlyphInternals;
  if (in.UncertaintyScene && this->UncertaintyExtinction > 0.0)
  {
    options.volumes.scene = in.UncertaintyScene.get();
    options.volumes.extinction = static_cast<float>(this->UncertaintyExtinction / in.WorldScale);
    options.volumes.emission = sightline::vec3(
      this->UncertaintyColor[0], this->UncertaintyColor[1], this->UncertaintyColor[2]);
  }
}

//------------------------------------------------------------------------------
vtkIdType vtkSightlineSHGlyphMapper::GetMemoryBytes()
{
  const vtkGlyphInternals& in = *this->GlyphInternals;
  std::size_t bytes = in.Glyphs.MemoryBytes() + in.Uncertainty.MemoryBytes();
  if (in.Drawn)
  {
    bytes += in.Drawn->memoryBytes();
  }
  if (in.UncertaintySet)
  {
    bytes += in.UncertaintySet->memoryBytes();
  }
  return static_cast<vtkIdType>(bytes);
}

//------------------------------------------------------------------------------
void vtkSightlineSHGlyphMapper::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "CoefficientArrayName: "
     << (this->CoefficientArrayName ? this->CoefficientArrayName : "(active scalars)") << "\n";
  os << indent << "Basis: " << this->GetBasisAsString()
     << (this->LegacyBasis ? " (legacy)" : "") << "\n";
  os << indent << "MaximumOrder: " << this->MaximumOrder << "\n";
  os << indent << "Normalization: " << this->GetNormalizationAsString() << "\n";
  os << indent << "ScaleFactor: " << this->ScaleFactor << "\n";
  os << indent << "SliceOrientation: " << this->GetSliceOrientationAsString() << "\n";
  os << indent << "SliceNumber: " << this->SliceNumber << "\n";
  os << indent << "DisplayExtent: " << this->DisplayExtent[0] << " " << this->DisplayExtent[1]
     << " " << this->DisplayExtent[2] << " " << this->DisplayExtent[3] << " "
     << this->DisplayExtent[4] << " " << this->DisplayExtent[5] << "\n";
  os << indent << "DataToWorldMatrix: " << (this->DataToWorldMatrix ? "set" : "(identity)") << "\n";
  os << indent << "DirectionToWorldMatrix: " << (this->DirectionToWorldMatrix ? "set" : "(world axes)")
     << "\n";
  os << indent << "MaskArrayName: " << (this->MaskArrayName ? this->MaskArrayName : "(none)")
     << "\n";
  os << indent << "Coloring: " << this->GetColoringAsString() << "\n";
  os << indent << "RadiusRange: " << this->RadiusRange[0] << " " << this->RadiusRange[1]
     << (this->RadiusRange[0] < this->RadiusRange[1] ? "" : " (automatic)") << "\n";
  os << indent << "NegativeLobes: " << this->GetNegativeLobesAsString() << "\n";
  os << indent << "NegativeLobeColor: " << this->NegativeLobeColor[0] << " "
     << this->NegativeLobeColor[1] << " " << this->NegativeLobeColor[2] << "\n";
  os << indent << "UncertaintyArrayName: "
     << (this->UncertaintyArrayName ? this->UncertaintyArrayName : "(none)") << "\n";
  os << indent << "UncertaintyExtinction: " << this->UncertaintyExtinction << "\n";
  os << indent << "UncertaintyColor: " << this->UncertaintyColor[0] << " "
     << this->UncertaintyColor[1] << " " << this->UncertaintyColor[2] << "\n";
  os << indent << "LastComputedBoxes: " << this->LastComputedBoxes << "\n";
}
