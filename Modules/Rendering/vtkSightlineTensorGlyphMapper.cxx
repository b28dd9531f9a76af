// SPDX-License-Identifier: BSD-3-Clause
#include "vtkSightlineTensorGlyphMapper.h"

#include "vtkDataArray.h"
#include "vtkDataSet.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"

#include "sightline/glyphs/SHGlyphPreparation.h"
#include "sightline/math/SymmetricTensor.h"

#include <algorithm>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

vtkStandardNewMacro(vtkSightlineTensorGlyphMapper);

namespace
{
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

/// Each tuple of `tensors` as the unique components of an order-`order` tensor, or, with
/// `toSH`, as the canonical SH coefficients of the same function in bands up to `shOrder`.
sightline::GlyphSource TensorSource(vtkDataArray* tensors, sightline::TensorLayout layout,
  int order, std::shared_ptr<const sightline::TensorToSH> toSH, int shOrder)
{
  sightline::GlyphSource source;
  source.pointCount = static_cast<std::size_t>(tensors->GetNumberOfTuples());
  source.order = toSH ? shOrder : order;
  source.convention = { sightline::SHBasis::Canonical, false };
  source.identity = tensors;
  // The layout decides what the values mean: a new layout must not reuse cached boxes.
  source.version = (tensors->GetMTime() << 3) | static_cast<std::uint64_t>(layout);
  auto tuple = std::make_shared<std::vector<double>>(tensors->GetNumberOfComponents());
  const int count = sightline::symmetricTensorComponentCount(order);
  // unique components, then all SH coefficients of the tensor
  auto work = std::make_shared<std::vector<double>>(2 * count);
  const int kept = sightline::shCoefficientCount(shOrder);
  source.read = [tensors, layout, order, toSH, tuple, work, count, kept](
                  std::size_t point, double* values)
  {
    tensors->GetTuple(static_cast<vtkIdType>(point), tuple->data());
    if (!toSH)
    {
      sightline::uniqueTensorComponents(layout, order, tuple->data(), values);
      return;
    }
    double* unique = work->data();
    double* sh = work->data() + count;
    sightline::uniqueTensorComponents(layout, order, tuple->data(), unique);
    toSH->apply(unique, sh);
    std::copy(sh, sh + kept, values);
  };
  return source;
}
} // namespace

//------------------------------------------------------------------------------
vtkSightlineTensorGlyphMapper::vtkSightlineTensorGlyphMapper() = default;

//------------------------------------------------------------------------------
vtkSightlineTensorGlyphMapper::~vtkSightlineTensorGlyphMapper()
{
  this->SetTensorArrayName(nullptr);
}

//------------------------------------------------------------------------------
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

//------------------------------------------------------------------------------
const char* vtkSightlineTensorGlyphMapper::GetShapeAsString()
{
  return this->Shape == SHAPE_ELLIPSOID ? "Ellipsoid" : "TensorFunction";
}

//------------------------------------------------------------------------------
std::shared_ptr<sightline::Geometry> vtkSightlineTensorGlyphMapper::BuildGlyphs(
  vtkDataSet* input, const sightline::GlyphRequest& request)
{
  vtkPointData* pointData = input->GetPointData();
  const bool named = this->TensorArrayName && *this->TensorArrayName;
  vtkDataArray* tensors = named ? pointData->GetArray(this->TensorArrayName)
                                : (pointData->GetTensors() ? pointData->GetTensors()
                                                           : pointData->GetScalars());
  std::string label = named ? "tensor array '" + std::string(this->TensorArrayName) + "'"
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
  sightline::TensorLayout layout;
  switch (this->TensorLayout)
  {
    case LAYOUT_SYMMETRIC_UNIQUE:
      layout = sightline::TensorLayout::SymmetricUnique;
      break;
    case LAYOUT_FULL:
      layout = sightline::TensorLayout::Full;
      break;
    case LAYOUT_VTK_SYMMETRIC:
      layout = sightline::TensorLayout::VTKSymmetric;
      break;
    case LAYOUT_VOIGT:
      layout = sightline::TensorLayout::Voigt;
      break;
    default:
      layout = sightline::guessTensorLayout(components);
      break;
  }
  const int order = sightline::tensorOrderInLayout(layout, components);
  if (order < 0)
  {
    vtkErrorMacro(<< "The " << label << " has " << components
                  << " components, which is no even-order tensor in the "
                  << (this->TensorLayout == LAYOUT_AUTOMATIC ? "known layouts" : "chosen layout ")
                  << (this->TensorLayout == LAYOUT_AUTOMATIC ? "" : this->GetTensorLayoutAsString())
                  << ": expected " << AcceptedCounts()
                  << ". (A 4-D NIfTI needs vtkNIFTIImageReader::TimeAsVectorOn().)");
    return nullptr;
  }
  if (!this->CheckPointArray(
        tensors, label, input->GetNumberOfPoints(), components, "no glyphs rendered"))
  {
    return nullptr;
  }
  this->TensorOrder = order;
  label += " (as tensors of order " + std::to_string(order) + ")";

  if (this->Shape == SHAPE_ELLIPSOID)
  {
    // vtkTensorGlyph's ellipsoid, straight from the eigen-decomposition.
    if (order != 2)
    {
      vtkErrorMacro(<< "Shape ELLIPSOID needs second-order tensors; the input has order "
                    << order << ". Use SHAPE_TENSOR_FUNCTION.");
      return nullptr;
    }
    if (this->IntersectionMethod != INTERSECT_EXACT)
    {
      vtkWarningMacro(<< "Ellipsoids are always intersected exactly; IntersectionMethod "
                      << this->GetIntersectionMethodAsString() << " is ignored.");
    }
    const sightline::PreparedEllipsoids ellipsoids =
      sightline::SHGlyphPreparation::prepareEllipsoids(
        TensorSource(tensors, layout, order, nullptr, order), request);
    this->ReportDroppedGlyphs(ellipsoids.drops, label);
    return this->MakeEllipsoidSet(input, ellipsoids);
  }

  // The tensor function as SH: bands above MaximumOrder are dropped as for SH input.
  const sightline::GlyphSource source = TensorSource(tensors, layout, order,
    std::make_shared<sightline::TensorToSH>(order), this->ApplyMaximumOrder(order));
  const sightline::PreparedSHGlyphs glyphs =
    this->PrepareSHGlyphs(this->GetGlyphPreparation(), source, request, label);
  return this->MakeSHGlyphSet(input, glyphs);
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
}
