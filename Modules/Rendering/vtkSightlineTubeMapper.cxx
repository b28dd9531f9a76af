// SPDX-License-Identifier: BSD-3-Clause
#include "vtkSightlineTubeMapper.h"

#include "SightlineMapperInput.h"

#include "SightlineKernelConversions.h"

#include "vtkCellArray.h"
#include "vtkDataArray.h"
#include "vtkFloatArray.h"
#include "vtkAlgorithmOutput.h"
#include "vtkIdList.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPointSet.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkStreamingDemandDrivenPipeline.h"
#include "vtkUnstructuredGrid.h"

#include "sightline/tubes/TubeBatchBuilder.h"
#include "sightline/tubes/TubeInterior.h"
#include "sightline/tubes/TubeSet.h"

#include <algorithm>
#include <cmath>
#include <exception>
#include <memory>
#include <vector>

vtkStandardNewMacro(vtkSightlineTubeMapper);

namespace
{
// Calls visit(cellId, ids) for each line or polyline cell of the input: vtkPolyData's lines
// (numbered after its verts), or the VTK_LINE and VTK_POLY_LINE cells of any other point set.
// ParaView's RedistributeDataSet (and D3, Append Datasets) hand polylines on as an unstructured
// grid, so each MPI rank's piece of a set of streamlines arrives as one.
template <typename Visit>
vtkIdType ForEachPolyline(vtkPointSet* input, vtkIdList* ids, Visit&& visit)
{
  vtkIdType found = 0;
  if (auto* poly = vtkPolyData::SafeDownCast(input))
  {
    vtkCellArray* lines = poly->GetLines();
    const vtkIdType firstLine = poly->GetNumberOfVerts();
    for (vtkIdType c = 0; lines && c < lines->GetNumberOfCells(); ++c)
    {
      lines->GetCellAtId(c, ids);
      visit(firstLine + c, ids);
      ++found;
    }
    return found;
  }
  if (auto* grid = vtkUnstructuredGrid::SafeDownCast(input))
  {
    for (vtkIdType c = 0; c < grid->GetNumberOfCells(); ++c)
    {
      const int type = grid->GetCellType(c);
      if (type == VTK_LINE || type == VTK_POLY_LINE)
      {
        grid->GetCellPoints(c, ids);
        visit(c, ids);
        ++found;
      }
    }
  }
  return found;
}
} // namespace

vtkSightlineTubeMapper::vtkSightlineTubeMapper() = default;

vtkSightlineTubeMapper::~vtkSightlineTubeMapper()
{
  this->SetRadiusArrayName(nullptr);
  this->SetPredecessorArrayName(nullptr);
}

int vtkSightlineTubeMapper::GetVaryRadius()
{
  if (this->VaryRadius >= 0)
  {
    return this->VaryRadius;
  }
  return this->RadiusArrayName && *this->RadiusArrayName ? VARY_RADIUS_BY_ABSOLUTE_SCALAR
                                                         : VARY_RADIUS_OFF;
}

bool vtkSightlineTubeMapper::ComputePointRadii(vtkPointSet* input, std::vector<float>& radius)
{
  const vtkIdType count = input->GetNumberOfPoints();
  radius.assign(static_cast<std::size_t>(count), static_cast<float>(this->Radius));
  const int vary = this->GetVaryRadius();
  if (vary != VARY_RADIUS_OFF)
  {
    const bool named = this->RadiusArrayName && *this->RadiusArrayName;
    vtkDataArray* array =
      named ? input->GetPointData()->GetArray(this->RadiusArrayName) : input->GetPointData()->GetScalars();
    const std::string label = "radius array " +
      (named ? "'" + std::string(this->RadiusArrayName) + "'" : std::string("(active scalars)"));
    if (!this->CheckPointArray(array, label, count, 1, "no tubes rendered", true))
    {
      return false;
    }
    double range[2];
    array->GetRange(range, 0);
    for (vtkIdType i = 0; i < count; ++i)
    {
      const double v = array->GetComponent(i, 0);
      radius[i] = static_cast<float>(vary == VARY_RADIUS_BY_ABSOLUTE_SCALAR
          ? v * this->RadiusScale
          : this->Radius *
            (1.0 + (this->RadiusFactor - 1.0) * (range[1] > range[0] ? (v - range[0]) / (range[1] - range[0]) : 0.0)));
    }
  }
  else if (!(std::isfinite(this->Radius) && this->Radius >= 0.0))
  {
    vtkErrorMacro(<< "Radius must be non-negative and finite, got " << this->Radius
                  << "; no tubes rendered.");
    return false;
  }
  return true;
}

std::shared_ptr<sightline::Geometry> vtkSightlineTubeMapper::BuildGeometry()
{
  this->NumberOfLinks = 0;
  this->BuiltLinkLayout = -1;
  this->BuiltChunkLinks = 0;
  this->Streamed = StreamedRuns();
  if (this->PullsInputPieces())
  {
    // Progress counts pieces; hidden-link culling then reports its own, under its own text.
    this->SetProgressText("reading and building tubes");
    auto tubes = this->BuildStreamedGeometry();
    this->SetProgressText(nullptr);
    return tubes;
  }
  if (this->StreamedPieces > 1 && this->GetNumberOfInputConnections(0) > 0)
  {
    vtkWarningMacro(<< "StreamedPieces (" << this->StreamedPieces << ") pulls pieces from a "
                    << "pipeline (a reader's output port); the input was given as data, which is "
                    << "whole already: drawn whole.");
  }
  // Called only with points to draw (an empty input draws nothing, quietly).
  vtkPointSet* input = vtkPointSet::SafeDownCast(this->GetDrawnInput());
  const vtkIdType count = input && input->GetPoints() ? input->GetNumberOfPoints() : 0;
  if (count == 0)
  {
    return nullptr;
  }

  std::vector<float> radius;
  if (!this->ComputePointRadii(input, radius))
  {
    return nullptr;
  }

  // Colours per point, or per polyline (a tractogram's per-streamline values: each streamline's
  // tubes take its colour).
  const auto inputColors = SightlineKernelConversions::ColorsByPointOrCell(this, input);
  const std::vector<std::uint32_t>& pointColors = inputColors.points;
  const std::vector<std::uint32_t>& cellColors = inputColors.cells;

  // Control points and their predecessors: the input's points with the predecessor array, or a
  // copy of each polyline's points (a point may be interior to several polylines).
  std::vector<sightline::dvec3> points;
  std::vector<float> radii;
  std::vector<std::int64_t> predecessors;
  std::vector<std::uint32_t> colors;
  auto add = [&](vtkIdType id, std::int64_t predecessor, vtkIdType cell = -1)
  {
    points.emplace_back();
    input->GetPoint(id, &points.back().x);
    radii.push_back(radius[id]);
    predecessors.push_back(predecessor);
    if (!pointColors.empty())
    {
      colors.push_back(pointColors[id]);
    }
    else if (!cellColors.empty() && cell >= 0)
    {
      colors.push_back(cellColors[static_cast<std::size_t>(cell)]);
    }
  };
  if (this->PredecessorArrayName && *this->PredecessorArrayName)
  {
    vtkDataArray* array = input->GetPointData()->GetArray(this->PredecessorArrayName);
    const std::string label = "predecessor array '" + std::string(this->PredecessorArrayName) + "'";
    if (!this->CheckPointArray(array, label, count, 1, "no tubes rendered", true))
    {
      return nullptr;
    }
    // A predecessor is a point index or -1: anything else (NaN, a fraction, a value no index
    // can have) is named as it is, not as whatever an integer conversion makes of it.
    // The leaves of a composite input are appended: a predecessor is an index into its own
    // leaf's points, which start at that leaf's offset.
    const std::vector<vtkIdType>& offsets = this->GetLeafPointOffsets();
    std::size_t leaf = 0;
    for (vtkIdType i = 0; i < count; ++i)
    {
      while (leaf + 1 < offsets.size() && offsets[leaf + 1] <= i)
      {
        ++leaf;
      }
      const vtkIdType first = offsets.empty() ? 0 : offsets[leaf];
      const vtkIdType end = leaf + 1 < offsets.size() ? offsets[leaf + 1] : count;
      const double v = array->GetComponent(i, 0);
      if (!(v >= -1.0 && v < double(end - first)) || v != std::floor(v))
      {
        vtkErrorMacro(<< "The " << label << " gives point " << i << " the predecessor " << v
                      << ", which is not -1 (none) or a point index in [0, " << end - first - 1
                      << "]" << (offsets.size() > 1 ? " of its leaf" : "")
                      << "; no tubes rendered.");
        return nullptr;
      }
      add(i, v < 0.0 ? -1 : static_cast<std::int64_t>(v) + first);
    }
  }
  else
  {
    // A polyline naming a point the input does not have is left out whole, with a warning:
    // its links would come from memory past the points.
    vtkNew<vtkIdList> ids;
    vtkIdType skipped = 0;
    const vtkIdType lineCount = ForEachPolyline(input, ids,
      [&](vtkIdType c, vtkIdList* cell)
      {
        const vtkIdType* first = cell->GetPointer(0);
        const vtkIdType* last = first + cell->GetNumberOfIds();
        const vtkIdType* bad =
          std::find_if(first, last, [count](vtkIdType id) { return id < 0 || id >= count; });
        if (bad != last)
        {
          if (skipped++ == 0)
          {
            vtkWarningMacro(<< "Polyline " << c << " names point " << *bad
                            << " but the input has " << count << " points (ids 0 to "
                            << count - 1 << "); such polylines are left out.");
          }
          return;
        }
        for (vtkIdType k = 0; k < cell->GetNumberOfIds(); ++k)
        {
          add(cell->GetId(k), k == 0 ? -1 : std::int64_t(points.size()) - 1, c);
        }
      });
    if (lineCount == 0)
    {
      vtkErrorMacro(<< "The input has no polylines; give line or polyline cells (vtkPolyData "
                       "lines or an unstructured grid's) or set PredecessorArrayName to a point "
                       "array of predecessor indices.");
      return nullptr;
    }
    if (skipped > 1)
    {
      vtkWarningMacro(<< skipped << " polylines name points the input does not have; they are left out.");
    }
    if (points.empty())
    {
      vtkErrorMacro(<< "No polyline names only points of the input; no tubes rendered.");
      return nullptr;
    }
  }

  try
  {
    // Large sets (tractograms) are limited by bytes per link, which chunks cut.
    int chosen = this->LinkLayout;
    if (chosen == LINKS_AUTOMATIC)
    {
      chosen = static_cast<vtkIdType>(points.size()) >= this->AutomaticChunkedLinks
        ? LINKS_CHUNKED
        : LINKS_COMBINED_ON_THE_FLY;
    }
    sightline::TubeLayout layout;
    layout.primitives = chosen == LINKS_CHUNKED ? sightline::TubeLayout::Primitives::Chunked
      : chosen >= LINKS_SEPARATE_ON_THE_FLY   ? sightline::TubeLayout::Primitives::Separate
                                              : sightline::TubeLayout::Primitives::Combined;
    layout.transforms = chosen % 2 == 1 && chosen != LINKS_CHUNKED
      ? sightline::TubeLayout::Transforms::Precomputed
      : sightline::TubeLayout::Transforms::OnTheFly;
    layout.chunkSize = this->ChunkLinksFor(double(points.size()));
    std::vector<sightline::vec3> local;
    const sightline::dvec3 origin = SightlineKernelConversions::ToLocalFrame(points, local);
    // The double points are not needed past here: at 10^7 links they are 240 MB of the build's
    // peak, which the tube set's own construction would otherwise stack on top of.
    std::vector<sightline::dvec3>().swap(points);
    auto tubes =
      std::make_shared<sightline::TubeSet>(origin, local, radii, predecessors, colors, layout);
    SightlineKernelConversions::WarnAboutReport(this, tubes->report());
    this->NumberOfLinks = static_cast<vtkIdType>(tubes->pointCount());
    this->BuiltLinkLayout = chosen;
    this->BuiltChunkLinks = chosen == LINKS_CHUNKED ? static_cast<int>(layout.chunkSize) : 0;
    return tubes;
  }
  catch (const std::exception& e)
  {
    vtkErrorMacro(<< "Could not build the tubes: " << e.what());
    return nullptr;
  }
}

//------------------------------------------------------------------------------
std::shared_ptr<sightline::Geometry> vtkSightlineTubeMapper::BuildOuterGeometry(
  const sightline::Geometry& whole)
{
  this->HiddenLinks = 0;
  this->LastCullingSeconds = this->LastCullingMarkSeconds = this->LastCullingTestSeconds = 0.0;
  const auto* tubes = dynamic_cast<const sightline::TubeSet*>(&whole);
  if (!this->HiddenLinkCulling || !tubes)
  {
    return nullptr;
  }
  sightline::OuterLinkReport report;
  sightline::OuterLinkOptions options;
  options.progress = SightlineKernelConversions::ProgressCallback(this);
  this->SetProgressText("finding hidden links");
  std::shared_ptr<sightline::TubeSet> outer = sightline::outerLinks(*tubes, options, &report);
  this->SetProgressText(nullptr);
  vtkDebugMacro(<< "Hidden-link culling: fill " << report.fill << ", voxel " << report.voxel
                << ", " << report.hiddenLinks << " of " << report.links << " hidden, "
                << report.seconds << " s (marking " << report.markSeconds << " s, testing "
                << report.keepSeconds << " s)");
  this->LastCullingSeconds = report.seconds;
  this->LastCullingMarkSeconds = report.markSeconds;
  this->LastCullingTestSeconds = report.keepSeconds;
  if (outer)
  {
    this->HiddenLinks = static_cast<vtkIdType>(report.hiddenLinks);
  }
  return outer;
}

//------------------------------------------------------------------------------
bool vtkSightlineTubeMapper::PullsInputPieces()
{
  // Data given as such (SetInputData: a vtkTrivialProducer) is whole already, and such a
  // producer hands every piece request the whole of it: it is drawn whole.
  return this->StreamedPieces > 1 && this->GetNumberOfInputConnections(0) > 0 &&
    !this->GetInputAlgorithm(0, 0)->IsA("vtkTrivialProducer");
}

//------------------------------------------------------------------------------
std::shared_ptr<sightline::Geometry> vtkSightlineTubeMapper::BuildStreamedGeometry()
{
  // What a piece alone cannot give is an error before any piece is read.
  if (this->LinkLayout != LINKS_AUTOMATIC && this->LinkLayout != LINKS_CHUNKED)
  {
    vtkErrorMacro(<< "StreamedPieces (" << this->StreamedPieces << ") builds chunked tubes; "
                  << "LinkLayout " << this->GetLinkLayoutAsString() << " needs the input whole. "
                  << "Set LinkLayout to LINKS_CHUNKED or LINKS_AUTOMATIC, or StreamedPieces to 1; "
                  << "no tubes rendered.");
    return nullptr;
  }
  if (this->PredecessorArrayName && *this->PredecessorArrayName)
  {
    vtkErrorMacro(<< "StreamedPieces draws polylines; predecessor indices (PredecessorArrayName '"
                  << this->PredecessorArrayName << "') can name points of other pieces. Set "
                  << "StreamedPieces to 1; no tubes rendered.");
    return nullptr;
  }
  if (this->GetVaryRadius() == VARY_RADIUS_BY_SCALAR)
  {
    vtkErrorMacro(<< "StreamedPieces cannot scale radii by the radius array's range "
                  << "(VARY_RADIUS_BY_SCALAR): that is the whole input's. Use "
                  << "VARY_RADIUS_BY_ABSOLUTE_SCALAR, or StreamedPieces 1; no tubes rendered.");
    return nullptr;
  }

  vtkAlgorithmOutput* connection = this->GetInputConnection(0, 0);
  vtkAlgorithm* producer = connection->GetProducer();
  const int port = connection->GetIndex();
  const int pieces = this->StreamedPieces;
  // Each piece is read and converted here while the one before is built on a worker thread
  // (sightline::TubeBatchBuilder, which calls nothing of VTK's).
  std::unique_ptr<sightline::TubeBatchBuilder> builder;
  sightline::TubeBatchBuilder::Batch batch;
  sightline::dvec3 origin(0.0);
  vtkIdType pointOffset = 0, cellOffset = 0, skipped = 0, lines = 0;
  bool colored = false;
  vtkNew<vtkIdList> ids;
  std::vector<float> radius;
  for (int piece = 0; piece < pieces; ++piece)
  {
    // Ask for this piece on the producer's output port (the others as they are).
    vtkNew<vtkInformationVector> requests;
    for (int p = 0; p < producer->GetNumberOfOutputPorts(); ++p)
    {
      vtkNew<vtkInformation> request;
      if (p == port)
      {
        request->Set(vtkStreamingDemandDrivenPipeline::UPDATE_PIECE_NUMBER(), piece);
        request->Set(vtkStreamingDemandDrivenPipeline::UPDATE_NUMBER_OF_PIECES(), pieces);
        request->Set(vtkStreamingDemandDrivenPipeline::UPDATE_NUMBER_OF_GHOST_LEVELS(), 0);
      }
      requests->Append(request);
    }
    if (!producer->Update(port, requests))
    {
      vtkErrorMacro(<< "The input's producer (" << producer->GetClassName() << ") failed on piece "
                    << piece << " of " << pieces << "; no tubes rendered.");
      return nullptr;
    }
    vtkDataObject* output = producer->GetOutputDataObject(port);
    for (vtkPointSet* input : SightlineMapperInput::PointSets(output))
    {
      const vtkIdType count = input->GetPoints() ? input->GetNumberOfPoints() : 0;
      const vtkIdType cells = input->GetNumberOfCells();
      if (count > 0 && cells > 0) // (a piece may hold no streamline, e.g. of chosen groups)
      {
        if (!this->ComputePointRadii(input, radius))
        {
          return nullptr;
        }
        const auto pieceColors = SightlineKernelConversions::ColorsByPointOrCell(this, input);
        const std::vector<std::uint32_t>& pointColors = pieceColors.points;
        const std::vector<std::uint32_t>& cellColors = pieceColors.cells;
        // Points relative to the first piece's centre: a tractogram's pieces share its extent.
        if (!builder)
        {
          std::vector<sightline::dvec3> world(static_cast<std::size_t>(count));
          for (vtkIdType i = 0; i < count; ++i)
          {
            input->GetPoint(i, &world[i].x);
          }
          std::vector<sightline::vec3> local;
          origin = SightlineKernelConversions::ToLocalFrame(world, local);
          colored = !pieceColors.empty();
          // Pieces of one reader hold about as many points each.
          const double expected = 1.05 * double(count) * pieces;
          this->BuiltChunkLinks = static_cast<int>(this->ChunkLinksFor(expected));
          builder = std::make_unique<sightline::TubeBatchBuilder>(
            origin, static_cast<unsigned>(this->BuiltChunkLinks), colored);
          builder->reserve(static_cast<std::size_t>(expected));
        }
        if (colored != !pieceColors.empty())
        {
          vtkErrorMacro(<< "Piece " << piece << " is " << (colored ? "not " : "")
                        << "coloured by scalars where the first piece was" << (colored ? "" : " not")
                        << "; give every piece the same arrays. No tubes rendered.");
          return nullptr;
        }
        // Float points (every tractogram reader's) read in place; others through GetPoint.
        const float* floats = nullptr;
        if (auto* array = vtkFloatArray::FastDownCast(input->GetPoints()->GetData()))
        {
          floats = array->GetPointer(0);
        }
        const std::size_t given = builder->pointsGiven();
        lines += ForEachPolyline(input, ids,
          [&](vtkIdType c, vtkIdList* cell)
          {
            const vtkIdType n = cell->GetNumberOfIds();
            const vtkIdType* first = cell->GetPointer(0);
            const vtkIdType* last = first + n;
            if (std::any_of(first, last, [count](vtkIdType id) { return id < 0 || id >= count; }))
            {
              if (skipped++ == 0)
              {
                vtkWarningMacro(<< "Polyline " << cellOffset + c << " names a point its piece does "
                                << "not have; such polylines are left out.");
              }
              return;
            }
            this->Streamed.FirstControlPoint.push_back(
              static_cast<std::uint32_t>(given + batch.points.size()));
            bool consecutive = true;
            sightline::dvec3 point;
            for (vtkIdType k = 0; k < n; ++k)
            {
              const vtkIdType id = first[k];
              consecutive = consecutive && (k == 0 || id == first[k - 1] + 1);
              if (floats)
              {
                point = sightline::dvec3(floats[3 * id], floats[3 * id + 1], floats[3 * id + 2]);
              }
              else
              {
                input->GetPoint(id, &point.x);
              }
              batch.points.push_back(sightline::vec3(point - origin));
              batch.radii.push_back(radius[static_cast<std::size_t>(id)]);
              if (colored)
              {
                batch.colors.push_back(
                  pointColors.empty() ? cellColors[static_cast<std::size_t>(c)] : pointColors[id]);
              }
            }
            batch.endRun();
            this->Streamed.Cell.push_back(cellOffset + c);
            this->Streamed.FirstPoint.push_back(n > 0 && consecutive ? pointOffset + first[0] : -1);
          });
        batch = builder->add(std::move(batch));
      }
      pointOffset += count;
      cellOffset += cells;
    }
    // The piece is not needed past here; released data also makes the next build read again.
    output->ReleaseData();
    this->UpdateProgress(double(piece + 1) / pieces);
  }
  if (skipped > 1)
  {
    vtkWarningMacro(<< skipped << " polylines name points their piece does not have; they are left out.");
  }
  if (!builder)
  {
    return nullptr; // no piece had points: nothing to draw, quietly
  }
  if (lines == 0)
  {
    vtkErrorMacro(<< "The input's pieces have no polylines; give line or polyline cells to stream "
                     "(or set StreamedPieces to 1).");
    return nullptr;
  }
  auto tubes = builder->finish();
  SightlineKernelConversions::WarnAboutReport(this, tubes->report());
  this->Streamed.FirstControlPoint.shrink_to_fit();
  this->Streamed.Cell.shrink_to_fit();
  this->Streamed.FirstPoint.shrink_to_fit();
  this->NumberOfLinks = static_cast<vtkIdType>(tubes->pointCount());
  this->BuiltLinkLayout = LINKS_CHUNKED;
  return tubes;
}

//------------------------------------------------------------------------------
void vtkSightlineTubeMapper::ComputeSelectionIds(
  std::vector<vtkIdType>& pointIds, std::vector<vtkIdType>& cellIds)
{
  auto* tubes = dynamic_cast<sightline::TubeSet*>(this->GetGeometry());
  // Selection index p (a primitive, or with chunks the link hit: Geometry::selectionIndex) as
  // the control points (in the order BuildGeometry gave them) of its link's end and start.
  auto linkOf = [tubes](std::size_t p, std::size_t& own, std::size_t& start)
  {
    const std::uint32_t node = tubes->nodeOfSelection(static_cast<std::uint32_t>(p));
    const std::int32_t predecessor = tubes->predecessorOf(node);
    own = tubes->sourceIndexOf(node);
    start = predecessor >= 0 ? tubes->sourceIndexOf(static_cast<std::uint32_t>(predecessor)) : own;
  };
  std::size_t own = 0, start = 0;
  if (tubes && !this->Streamed.FirstControlPoint.empty())
  {
    // Streamed: the input is gone; each tube knows its polyline and its first point's id.
    const auto& starts = this->Streamed.FirstControlPoint;
    for (std::size_t p = 0; p < pointIds.size(); ++p)
    {
      linkOf(p, own, start);
      const std::size_t run =
        static_cast<std::size_t>(std::upper_bound(starts.begin(), starts.end(), own) - starts.begin()) - 1;
      cellIds[p] = this->Streamed.Cell[run];
      const vtkIdType firstPoint = this->Streamed.FirstPoint[run];
      pointIds[p] = firstPoint >= 0 ? firstPoint + static_cast<vtkIdType>(start - starts[run]) : -1;
    }
    return;
  }
  vtkPointSet* input = vtkPointSet::SafeDownCast(this->GetDrawnInput());
  if (!tubes || !input)
  {
    return;
  }
  // The input point and cell of each control point BuildGeometry gave the tube set: the input's
  // points in order with a predecessor array, else each kept polyline's points in turn (the
  // same polylines BuildGeometry keeps: those naming only points the input has).
  const vtkIdType count = input->GetNumberOfPoints();
  std::vector<vtkIdType> controlPoint, controlCell;
  if (this->PredecessorArrayName && *this->PredecessorArrayName)
  {
    controlPoint.resize(static_cast<std::size_t>(count));
    for (vtkIdType i = 0; i < count; ++i)
    {
      controlPoint[i] = i;
    }
    controlCell.assign(controlPoint.size(), -1);
  }
  else
  {
    vtkNew<vtkIdList> ids;
    ForEachPolyline(input, ids,
      [&](vtkIdType c, vtkIdList* cell)
      {
        const vtkIdType* first = cell->GetPointer(0);
        const vtkIdType* last = first + cell->GetNumberOfIds();
        if (std::any_of(first, last, [count](vtkIdType id) { return id < 0 || id >= count; }))
        {
          return;
        }
        controlPoint.insert(controlPoint.end(), first, last);
        controlCell.insert(controlCell.end(), cell->GetNumberOfIds(), c);
      });
  }
  for (std::size_t p = 0; p < pointIds.size(); ++p)
  {
    linkOf(p, own, start);
    if (own < controlPoint.size() && start < controlPoint.size())
    {
      pointIds[p] = controlPoint[start];
      cellIds[p] = controlCell[own];
    }
  }
}

unsigned vtkSightlineTubeMapper::ChunkLinksFor(double points) const
{
  if (this->ChunkLinks > 0)
  {
    return static_cast<unsigned>(this->ChunkLinks);
  }
  return points >= double(this->AutomaticLongChunkLinks) ? 16u : sightline::TubeLayout::kDefaultChunkSize;
}

//------------------------------------------------------------------------------
const char* vtkSightlineTubeMapper::GetLinkLayoutAsString()
{
  switch (this->LinkLayout)
  {
    case LINKS_COMBINED_PRECOMPUTED:
      return "CombinedPrecomputed";
    case LINKS_SEPARATE_ON_THE_FLY:
      return "SeparateOnTheFly";
    case LINKS_SEPARATE_PRECOMPUTED:
      return "SeparatePrecomputed";
    case LINKS_CHUNKED:
      return "Chunked";
    case LINKS_AUTOMATIC:
      return "Automatic";
    default:
      return "CombinedOnTheFly";
  }
}

double vtkSightlineTubeMapper::ComputeReach(vtkDataObject* data)
{
  double reach = 0.0;
  const int vary = this->GetVaryRadius();
  for (vtkPointSet* points : SightlineMapperInput::PointSets(data))
  {
    if (points->GetNumberOfPoints() == 0)
    {
      continue;
    }
    const bool named = this->RadiusArrayName && *this->RadiusArrayName;
    vtkDataArray* array = vary == VARY_RADIUS_OFF ? nullptr
      : named                                     ? points->GetPointData()->GetArray(this->RadiusArrayName)
                                                  : points->GetPointData()->GetScalars();
    double largest = std::isfinite(this->Radius) ? std::abs(this->Radius) : 0.0;
    if (array && vary == VARY_RADIUS_BY_ABSOLUTE_SCALAR)
    {
      largest = SightlineMapperInput::LargestRadius(array, this->Radius, this->RadiusScale);
    }
    else if (array && std::isfinite(this->RadiusFactor))
    {
      // Radius * (1 + (factor - 1) u) with u in [0, 1]: largest at an end.
      largest = std::max(largest, std::abs(this->Radius * this->RadiusFactor));
    }
    reach = std::max(reach, largest);
  }
  return reach;
}

void vtkSightlineTubeMapper::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Radius: " << this->Radius << "\n";
  os << indent << "RadiusArrayName: " << (this->RadiusArrayName ? this->RadiusArrayName : "(none)") << "\n";
  os << indent << "VaryRadius: " << this->GetVaryRadius() << "\n";
  os << indent << "RadiusScale: " << this->RadiusScale << "\n";
  os << indent << "RadiusFactor: " << this->RadiusFactor << "\n";
  os << indent << "PredecessorArrayName: "
     << (this->PredecessorArrayName ? this->PredecessorArrayName : "(polylines)") << "\n";
  os << indent << "LinkLayout: " << this->GetLinkLayoutAsString() << "\n";
  os << indent << "BuiltLinkLayout: " << this->BuiltLinkLayout << "\n";
  os << indent << "AutomaticChunkedLinks: " << this->AutomaticChunkedLinks << "\n";
  os << indent << "ChunkLinks: " << this->ChunkLinks << "\n";
  os << indent << "AutomaticLongChunkLinks: " << this->AutomaticLongChunkLinks << "\n";
  os << indent << "NumberOfLinks: " << this->NumberOfLinks << "\n";
  os << indent << "StreamedPieces: " << this->StreamedPieces << "\n";
  os << indent << "HiddenLinkCulling: " << this->HiddenLinkCulling << "\n";
  os << indent << "HiddenLinks: " << this->HiddenLinks << "\n";
}
