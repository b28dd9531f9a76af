// SPDX-License-Identifier: BSD-3-Clause
#include "vtkSightlineSHGlyphMapper.h"

#include "vtkDataArray.h"
#include "vtkDataSet.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"

#include "sightline/core/EmbreeScene.h"
#include "sightline/core/Renderer.h"
#include "sightline/glyphs/SHGlyphPreparation.h"
#include "sightline/glyphs/SHGlyphSet.h"

#include <algorithm>
#include <exception>
#include <sstream>
#include <string>
#include <vector>

vtkStandardNewMacro(vtkSightlineSHGlyphMapper);

namespace
{
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

/// The first shCoefficientCount(order) components of each tuple of `array`.
sightline::GlyphSource CoefficientSource(
  vtkDataArray* array, int order, const sightline::SHConvention& convention)
{
  sightline::GlyphSource source;
  source.pointCount = static_cast<std::size_t>(array->GetNumberOfTuples());
  source.order = order;
  source.convention = convention;
  source.identity = array;
  source.version = array->GetMTime();
  auto tuple = std::make_shared<std::vector<double>>(array->GetNumberOfComponents());
  const int count = sightline::shCoefficientCount(order);
  source.read = [array, tuple, count](std::size_t point, double* values)
  {
    array->GetTuple(static_cast<vtkIdType>(point), tuple->data());
    std::copy(tuple->begin(), tuple->begin() + count, values);
  };
  return source;
}
} // namespace

/// The uncertainty glyphs: their own per-point cache, glyph set and volume scene.
class vtkSightlineSHGlyphMapper::vtkSHInternals
{
public:
  sightline::SHGlyphPreparation Uncertainty;
  std::shared_ptr<sightline::Geometry> UncertaintySet;
  std::unique_ptr<sightline::EmbreeScene> UncertaintyScene;
};

//------------------------------------------------------------------------------
vtkSightlineSHGlyphMapper::vtkSightlineSHGlyphMapper()
  : SHInternals(new vtkSHInternals)
{
}

//------------------------------------------------------------------------------
vtkSightlineSHGlyphMapper::~vtkSightlineSHGlyphMapper()
{
  this->SetCoefficientArrayName(nullptr);
  this->SetUncertaintyArrayName(nullptr);
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
std::shared_ptr<sightline::Geometry> vtkSightlineSHGlyphMapper::BuildGlyphs(
  vtkDataSet* input, const sightline::GlyphRequest& request)
{
  vtkSHInternals& in = *this->SHInternals;
  in.UncertaintySet.reset();
  in.UncertaintyScene.reset();
  const vtkIdType points = input->GetNumberOfPoints();
  vtkPointData* pointData = input->GetPointData();

  // The coefficient array and the order its component count stands for.
  const bool named = this->CoefficientArrayName && *this->CoefficientArrayName;
  vtkDataArray* coefficients =
    named ? pointData->GetArray(this->CoefficientArrayName) : pointData->GetScalars();
  const std::string label = named
    ? "coefficient array '" + std::string(this->CoefficientArrayName) + "'"
    : std::string("active point scalars (the coefficient array)");
  if (!coefficients)
  {
    vtkErrorMacro(<< "The input has no " << label
                  << "; set CoefficientArrayName to the point-data array of SH coefficients.");
    return nullptr;
  }
  const int components = coefficients->GetNumberOfComponents();
  int order = sightline::shOrderFromCount(static_cast<std::size_t>(components));
  if (order < 0)
  {
    vtkErrorMacro(<< "The " << label << " has " << components
                  << " components, which is no SH order: expected one of " << CountsOfOrders()
                  << ". (A 4-D NIfTI needs vtkNIFTIImageReader::TimeAsVectorOn().)");
    return nullptr;
  }
  if (!this->CheckPointArray(coefficients, label, points, components, "no glyphs rendered"))
  {
    return nullptr;
  }
  order = this->ApplyMaximumOrder(order);
  const sightline::SHConvention convention{ this->Basis == TOURNIER07
      ? sightline::SHBasis::Tournier07
      : sightline::SHBasis::Descoteaux07,
    this->LegacyBasis };

  // The uncertainty array is checked before anything is drawn: one that does not describe
  // these points is an error, one that is no SH leaves the glyphs without uncertainty.
  vtkDataArray* uncertainty = nullptr;
  int uncertaintyOrder = -1;
  std::string uncertaintyLabel;
  if (this->UncertaintyArrayName && *this->UncertaintyArrayName)
  {
    uncertaintyLabel = "uncertainty array '" + std::string(this->UncertaintyArrayName) + "'";
    uncertainty = pointData->GetArray(this->UncertaintyArrayName);
    if (!uncertainty)
    {
      vtkErrorMacro(<< "The " << uncertaintyLabel
                    << " is not in the input's point data; drawing without uncertainty.");
    }
    else if ((uncertaintyOrder = sightline::shOrderFromCount(
                static_cast<std::size_t>(uncertainty->GetNumberOfComponents()))) < 0)
    {
      vtkErrorMacro(<< "The " << uncertaintyLabel << " has "
                    << uncertainty->GetNumberOfComponents()
                    << " components, which is no SH order: expected one of "
                    << CountsOfOrders() << ". Drawing without uncertainty.");
      uncertainty = nullptr;
    }
    else if (!this->CheckPointArray(uncertainty, uncertaintyLabel, points,
               uncertainty->GetNumberOfComponents(), "no glyphs rendered"))
    {
      return nullptr;
    }
  }

  const sightline::PreparedSHGlyphs glyphs = this->PrepareSHGlyphs(this->GetGlyphPreparation(),
    CoefficientSource(coefficients, order, convention), request, label);
  std::shared_ptr<sightline::Geometry> geometry = this->MakeSHGlyphSet(input, glyphs);
  if (!geometry || !uncertainty)
  {
    return geometry;
  }

  // Uncertainty glyphs: the same points and scale factors, drawn as a volume.
  const sightline::PreparedSHGlyphs enclosing = in.Uncertainty.prepareAlongside(
    CoefficientSource(uncertainty, uncertaintyOrder, convention), glyphs, request);
  this->ReportDroppedGlyphs(enclosing.drops, uncertaintyLabel);
  this->LastComputedBoxes += static_cast<vtkIdType>(enclosing.computedBoxes);
  this->LastLooseBoxes += static_cast<vtkIdType>(enclosing.looseBoxCount);
  in.UncertaintySet = this->MakeSHGlyphSet(input, enclosing, true);
  if (in.UncertaintySet && in.UncertaintySet->size() > 0)
  {
    in.UncertaintyScene = std::make_unique<sightline::EmbreeScene>();
    in.UncertaintyScene->add(in.UncertaintySet);
    in.UncertaintyScene->commit();
  }
  return geometry;
}

//------------------------------------------------------------------------------
void vtkSightlineSHGlyphMapper::ConfigureRender(sightline::RenderOptions& options)
{
  vtkSHInternals& in = *this->SHInternals;
  if (in.UncertaintyScene && this->UncertaintyExtinction > 0.0)
  {
    options.volumes.scene = in.UncertaintyScene.get();
    options.volumes.extinction = static_cast<float>(this->UncertaintyExtinction / this->WorldScale);
    options.volumes.emission = sightline::vec3(
      this->UncertaintyColor[0], this->UncertaintyColor[1], this->UncertaintyColor[2]);
  }
}

//------------------------------------------------------------------------------
vtkIdType vtkSightlineSHGlyphMapper::GetMemoryBytes()
{
  const vtkSHInternals& in = *this->SHInternals;
  std::size_t bytes = in.Uncertainty.memoryBytes();
  if (in.UncertaintySet)
  {
    bytes += in.UncertaintySet->memoryBytes();
  }
  return this->Superclass::GetMemoryBytes() + static_cast<vtkIdType>(bytes);
}

//------------------------------------------------------------------------------
void vtkSightlineSHGlyphMapper::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "CoefficientArrayName: "
     << (this->CoefficientArrayName ? this->CoefficientArrayName : "(active scalars)") << "\n";
  os << indent << "Basis: " << this->GetBasisAsString()
     << (this->LegacyBasis ? " (legacy)" : "") << "\n";
  os << indent << "UncertaintyArrayName: "
     << (this->UncertaintyArrayName ? this->UncertaintyArrayName : "(none)") << "\n";
  os << indent << "UncertaintyExtinction: " << this->UncertaintyExtinction << "\n";
  os << indent << "UncertaintyColor: " << this->UncertaintyColor[0] << " "
     << this->UncertaintyColor[1] << " " << this->UncertaintyColor[2] << "\n";
}
