#include "vtkSightlineTensorGlyphMapper.h"

#include "vtkDataSet.h"
#include "vtkDoubleArray.h"
#include "vtkMath.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkSmartPointer.h"

#include "sightline/glyphs/EllipsoidSet.h"
#include "sightline/glyphs/SHGlyphSet.h"
#include "sightline/math/SymmetricTensor.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <sstream>

vtkStandardNewMacro(vtkSightlineTensorGlyphMapper);

namespace
{
/// 3^n, or -1 when it would not be a tensor size we read.
long long FullCount(int order)
{
  long long count = 1;
  for (int i = 0; i < order; ++i)
  {
    count *= 3;
  }
  return count;
}

std::string AcceptedCounts()
{
  std::ostringstream counts;
  counts << "unique components ";
  for (int n = 0; n <= sightline::kMaxTensorOrder; n += 2)
  {
    counts << (n ? ", " : "") << sightline::symmetricTensorComponentCount(n) << " (order " << n
           << ")";
  }
  counts << "; full tensors 9, 81, 729 (orders 2, 4, 6); VTK's symmetric 6; Voigt 36";
  return counts.str();
}
} // namespace

/// The tensor array converted to canonical SH coefficients, rebuilt when the array, its
/// contents or the layout change (the superclass's per-point caches key on this array).
class vtkSightlineTensorGlyphMapper::vtkTensorInternals
{
public:
  vtkNew<vtkDoubleArray> Coefficients;
  vtkDataArray* Source = nullptr;
  vtkMTimeType SourceTime = 0;
  int Layout = -1;
  int Order = -1;
};

vtkSightlineTensorGlyphMapper::vtkSightlineTensorGlyphMapper()
  : TensorInternals(new vtkTensorInternals)
{
  this->TensorInternals->Coefficients->SetName("TensorAsSH");
}

vtkSightlineTensorGlyphMapper::~vtkSightlineTensorGlyphMapper()
{
  this->SetTensorArrayName(nullptr);
}

const char* vtkSightlineTensorGlyphMapper::GetTensorLayoutAsString()
{
  switch (this->TensorLayout)
  {
    case LAYOUT_SYMMETRIC_UNIQUE:
      return "SymmetricUnique";
    case LAYOUT_FULL:
      return "Full";
    case LAYOUT_VTK_SYMMETRIC:
      return "VTKSymmetric";
    case LAYOUT_VOIGT:
      return "Voigt";
    default:
      return "Automatic";
  }
}

const char* vtkSightlineTensorGlyphMapper::GetShapeAsString()
{
  return this->Shape == SHAPE_ELLIPSOID ? "Ellipsoid" : "TensorFunction";
}

const char* vtkSightlineTensorGlyphMapper::GetIntersectionMethodAsString()
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
vtkDataArray* vtkSightlineTensorGlyphMapper::SelectCoefficients(
  vtkDataSet* input, int& order, bool& canonical, std::string& label)
{
  vtkPointData* pointData = input->GetPointData();
  const bool named = this->TensorArrayName && *this->TensorArrayName;
  vtkDataArray* tensors = named ? pointData->GetArray(this->TensorArrayName)
                                : (pointData->GetTensors() ? pointData->GetTensors()
                                                           : pointData->GetScalars());
  label = named ? "tensor array '" + std::string(this->TensorArrayName) + "'"
                : std::string("active point tensors (or scalars)");
  this->TensorOrder = -1;
  if (!tensors)
  {
    vtkErrorMacro(<< "The input has no " << label
                  << "; set TensorArrayName to the point-data array of tensors.");
    return nullptr;
  }

  // The layout and order the component count stands for.
  const int components = tensors->GetNumberOfComponents();
  int layout = this->TensorLayout;
  int tensorOrder = -1;
  auto uniqueOrder = [components]()
  {
    for (int n = 0; n <= sightline::kMaxTensorOrder; n += 2)
    {
      if (sightline::symmetricTensorComponentCount(n) == components)
      {
        return n;
      }
    }
    return -1;
  };
  auto fullOrder = [components]()
  {
    for (int n = 2; n <= 6; n += 2)
    {
      if (FullCount(n) == components)
      {
        return n;
      }
    }
    return -1;
  };
  if (layout == LAYOUT_AUTOMATIC)
  {
    layout = components == 6 ? LAYOUT_VTK_SYMMETRIC
      : components == 36     ? LAYOUT_VOIGT
      : fullOrder() > 0      ? LAYOUT_FULL
                             : LAYOUT_SYMMETRIC_UNIQUE;
  }
  switch (layout)
  {
    case LAYOUT_SYMMETRIC_UNIQUE:
      tensorOrder = uniqueOrder();
      break;
    case LAYOUT_FULL:
      tensorOrder = fullOrder();
      break;
    case LAYOUT_VTK_SYMMETRIC:
      tensorOrder = components == 6 ? 2 : -1;
      break;
    default:
      tensorOrder = components == 36 ? 4 : -1;
      break;
  }
  if (tensorOrder < 0)
  {
    vtkErrorMacro(<< "The " << label << " has " << components
                  << " components, which is no even-order tensor in the "
                  << (this->TensorLayout == LAYOUT_AUTOMATIC ? "known layouts" : "chosen layout ")
                  << (this->TensorLayout == LAYOUT_AUTOMATIC ? "" : this->GetTensorLayoutAsString())
                  << ": expected " << AcceptedCounts()
                  << ". (A 4-D NIfTI needs vtkNIFTIImageReader::TimeAsVectorOn().)");
    return nullptr;
  }

  // Convert every point once: the superclass gathers slices from the converted array.
  vtkTensorInternals& in = *this->TensorInternals;
  if (in.Source != tensors || in.SourceTime != tensors->GetMTime() || in.Layout != layout ||
    in.Order != tensorOrder)
  {
    const vtkIdType points = tensors->GetNumberOfTuples();
    const int count = sightline::symmetricTensorComponentCount(tensorOrder);
    in.Coefficients->SetNumberOfComponents(count);
    in.Coefficients->SetNumberOfTuples(points);
    const sightline::TensorToSH map(tensorOrder);
    tbb::parallel_for(vtkIdType(0), points,
      [&](vtkIdType id)
      {
        std::vector<double> tuple(components);
        tensors->GetTuple(id, tuple.data());
        std::vector<double> unique;
        switch (layout)
        {
          case LAYOUT_SYMMETRIC_UNIQUE:
            unique = tuple;
            break;
          case LAYOUT_FULL:
            unique = sightline::symmetricPartFromFull(tensorOrder, tuple.data());
            break;
          case LAYOUT_VTK_SYMMETRIC: // XX, YY, ZZ, XY, YZ, XZ to xx, xy, xz, yy, yz, zz
            unique = { tuple[0], tuple[3], tuple[5], tuple[1], tuple[4], tuple[2] };
            break;
          default:
          {
            const std::vector<double> full = sightline::stiffnessFromVoigt(tuple.data());
            unique = sightline::symmetricPartFromFull(4, full.data());
            break;
          }
        }
        map.apply(unique.data(), in.Coefficients->GetPointer(id * count));
      });
    in.Coefficients->Modified();
    in.Source = tensors;
    in.SourceTime = tensors->GetMTime();
    in.Layout = layout;
    in.Order = tensorOrder;
  }
  this->TensorOrder = tensorOrder;
  order = tensorOrder;
  canonical = true;
  label += " (as tensors of order " + std::to_string(tensorOrder) + ")";
  return in.Coefficients;
}

//------------------------------------------------------------------------------
std::shared_ptr<sightline::Geometry> vtkSightlineTensorGlyphMapper::CreateGlyphGeometry(
  const std::vector<sightline::vec3>& centers, const std::vector<float>& values, int order,
  sightline::SHGlyphOptions& options, const std::vector<float>& scales,
  const std::vector<std::uint32_t>& colors, const std::vector<sightline::vec3>& halfExtents)
{
  if (this->Shape != SHAPE_ELLIPSOID)
  {
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
    return this->Superclass::CreateGlyphGeometry(
      centers, values, order, options, scales, colors, halfExtents);
  }

  // vtkTensorGlyph's ellipsoid: eigenvectors scaled by |eigenvalues| (flat ones kept visible).
  if (order != 2)
  {
    vtkErrorMacro(<< "Shape ELLIPSOID needs second-order tensors; the input has order " << order
                  << ". Use SHAPE_TENSOR_FUNCTION.");
    return nullptr;
  }
  if (this->IntersectionMethod != INTERSECT_EXACT)
  {
    vtkWarningMacro(<< "Ellipsoids are always intersected exactly; IntersectionMethod "
                    << this->GetIntersectionMethodAsString() << " is ignored.");
  }
  if (options.coloring == sightline::SHColoring::Radius)
  {
    vtkWarningMacro(<< "Ellipsoids are coloured per glyph; colouring by direction instead of "
                       "by radius.");
    options.coloring = sightline::SHColoring::Direction;
  }
  const sightline::TensorToSH map(2);
  std::vector<sightline::dmat3> axes(centers.size());
  std::vector<std::uint32_t> glyphColors;
  if (options.coloring == sightline::SHColoring::PerGlyph)
  {
    glyphColors = colors;
  }
  else if (options.coloring == sightline::SHColoring::Direction)
  {
    glyphColors.resize(centers.size());
  }
  for (std::size_t g = 0; g < centers.size(); ++g)
  {
    double sh[6], t[6];
    std::copy(values.begin() + 6 * g, values.begin() + 6 * g + 6, sh);
    map.inverse(sh, t); // xx, xy, xz, yy, yz, zz
    double a[3][3] = { { t[0], t[1], t[2] }, { t[1], t[3], t[4] }, { t[2], t[4], t[5] } };
    double w[3], v[3][3];
    vtkMath::Diagonalize3x3(a, w, v); // eigenvectors in the columns of v
    double largest = 0.0;
    int principal = 0;
    for (int i = 0; i < 3; ++i)
    {
      if (std::abs(w[i]) > largest)
      {
        largest = std::abs(w[i]);
        principal = i;
      }
    }
    for (int c = 0; c < 3; ++c)
    {
      const double length = scales[g] * std::max(std::abs(w[c]), 1e-3 * largest);
      axes[g][c] = sightline::dvec3(v[0][c], v[1][c], v[2][c]) * length;
    }
    if (options.coloring == sightline::SHColoring::Direction)
    {
      glyphColors[g] = sightline::packRGBA8(
        static_cast<std::uint8_t>(std::lround(255.0 * std::abs(v[0][principal]))),
        static_cast<std::uint8_t>(std::lround(255.0 * std::abs(v[1][principal]))),
        static_cast<std::uint8_t>(std::lround(255.0 * std::abs(v[2][principal]))));
    }
  }
  auto ellipsoids = std::make_shared<sightline::EllipsoidSet>(centers, axes, glyphColors);
  for (const std::string& reason : ellipsoids->report().reasons)
  {
    vtkWarningMacro(<< reason << ".");
  }
  return ellipsoids;
}

//------------------------------------------------------------------------------
vtkIdType vtkSightlineTensorGlyphMapper::GetMemoryBytes()
{
  const vtkDoubleArray* converted = this->TensorInternals->Coefficients;
  return this->Superclass::GetMemoryBytes() +
    static_cast<vtkIdType>(const_cast<vtkDoubleArray*>(converted)->GetDataSize() * sizeof(double));
}

//------------------------------------------------------------------------------
void vtkSightlineTensorGlyphMapper::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "TensorArrayName: "
     << (this->TensorArrayName ? this->TensorArrayName : "(active tensors or scalars)") << "\n";
  os << indent << "TensorLayout: " << this->GetTensorLayoutAsString() << "\n";
  os << indent << "TensorOrder: " << this->TensorOrder << "\n";
  os << indent << "Shape: " << this->GetShapeAsString() << "\n";
  os << indent << "IntersectionMethod: " << this->GetIntersectionMethodAsString() << "\n";
  os << indent << "MarchingStepSize: " << this->MarchingStepSize << "\n";
  os << indent << "MarchingBisectionSteps: " << this->MarchingBisectionSteps << "\n";
  os << indent << "MarchingLinearInterpolation: " << this->MarchingLinearInterpolation << "\n";
  os << indent << "MarchingCentreRefinement: " << this->MarchingCentreRefinement << "\n";
  os << indent << "SubdivisionTolerance: " << this->SubdivisionTolerance << "\n";
}
