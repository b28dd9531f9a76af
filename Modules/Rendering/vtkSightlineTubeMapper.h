// SPDX-License-Identifier: BSD-3-Clause
/**
 * @class   vtkSightlineTubeMapper
 * @brief   Ray-traces generalized tubes: spheres at the points joined by tangential cone stumps.
 *
 * The tube through points with radii is the union of their spheres and, for every link, the
 * cone stump tangent to both spheres (Han et al. 2019): exact silhouettes and depth, varying
 * radius, bifurcations without seams. Input (vtkPolyData or any vtkPointSet):
 * - polylines: every line cell is a tube through its points (points shared by several cells,
 *   e.g. a branch point, are joined into each): vtkPolyData lines, or the VTK_LINE and
 *   VTK_POLY_LINE cells of a vtkUnstructuredGrid (as ParaView's RedistributeDataSet hands on
 *   each MPI rank's piece of a set of streamlines);
 * - or, with PredecessorArrayName set (e.g. "ParentIndex" of vtkSightlineSWCReader), each point
 *   linked to the point whose index the array gives (-1: none); bifurcations are points named by
 *   several others. Cyclic links and indices out of range are errors.
 * - or a composite dataset of these (vtkMultiBlockDataSet, vtkPartitionedDataSet...): the
 *   tubes of every non-empty leaf; a leaf's predecessor indices refer to its own points.
 *
 * Radius: the constant Radius, or from a point array (RadiusArrayName, or the active scalars)
 * as vtkTubeFilter's VaryRadius modes do: VARY_RADIUS_BY_ABSOLUTE_SCALAR (radius = value times
 * RadiusScale; the default when an array is named) or VARY_RADIUS_BY_SCALAR (Radius at the
 * array's minimum up to Radius times RadiusFactor at its maximum). Points with a negative or
 * non-finite radius or position are dropped with their links, with a warning.
 *
 * Colour: VTK's scalar colouring per point or per polyline cell (ScalarVisibility, lookup table;
 * cell data colour a whole polyline, e.g. a tractogram's per-streamline values) or the actor's.
 *
 * Opacity: with the actor's opacity below 1 the tubes are drawn as the union of their solids
 * (Han et al. 2019, Section 4.3): only where a ray enters or leaves the union is a surface
 * drawn, so overlapping links and bifurcations show no interior surfaces, and a camera inside
 * a tube sees its wall from inside. Opaque actors take the cheaper first-hit path. See
 * vtkSightlineMapper for how translucent actors composite with the rest of the scene.
 *
 * Selection (vtkHardwareSelector, see vtkSightlineMapper): a pixel of a link (the cone stump
 * from a point's predecessor to it, with the point's sphere) selects the polyline cell holding
 * the link (CELLS; none when links come from PredecessorArrayName) and the link's start point,
 * the predecessor (POINTS; the point itself for a tube's first sphere). Translucent tubes are
 * selected at their nearest surface.
 *
 * LinkLayout picks one of the paper's four implementation choices (Table 1) or the chunked
 * layout (runs of up to ChunkLinks consecutive links as one BVH primitive, for tractograms of
 * 10^7 links and more); they draw the same image and differ in memory and speed (see
 * Benchmarks/README.md and Documentation/tubes.md). The default, LINKS_AUTOMATIC, takes
 * combined links with stumps computed on the fly (20 bytes per link plus ~94 of BVH; the
 * fastest or within 5 % of it) below AutomaticChunkedLinks control points, and chunked links
 * (8-link chunks: 11 bytes per link from float16 files, 15 from float32 ones, plus ~9 of
 * Embree's compact BVH; frames about 2 to 3 times slower) from there on, where memory is what
 * limits, and 16-link chunks from AutomaticLongChunkLinks points.
 *
 * Streaming (StreamedPieces > 1): for tractograms whose poly data would not fit beside their
 * tubes, the mapper asks its input's producer for pieces 0 to StreamedPieces - 1 of its output
 * one after the other (as an MPI rank asks for its own), adds each piece's polylines to chunked
 * tubes (sightline::TubeRunBuilder) and releases the piece: the whole poly data never exists.
 * Readers that answer piece requests (vtkSightlineTRXReader, vtkSightlineTCKReader,
 * vtkSightlineTrackVisReader) read only each piece's streamlines. See StreamedPieces for what
 * streaming needs.
 *
 * @sa vtkSightlineSWCReader vtkSightlineTrackVisReader vtkSightlineTCKReader vtkTubeFilter
 */
#ifndef vtkSightlineTubeMapper_h
#define vtkSightlineTubeMapper_h

#include "SightlineRenderingModule.h" // for export macro
#include "vtkSightlineMapper.h"

#include <cstdint> // for std::uint32_t

class vtkPointSet;

class SIGHTLINERENDERING_EXPORT vtkSightlineTubeMapper : public vtkSightlineMapper
{
public:
  static vtkSightlineTubeMapper* New();
  vtkTypeMacro(vtkSightlineTubeMapper, vtkSightlineMapper);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /**
   * Radius without an array, and the base radius of VARY_RADIUS_BY_SCALAR. Default 1.
   */
  vtkSetMacro(Radius, double);
  vtkGetMacro(Radius, double);

  /**
   * Point array of radii (or of the scalar mapped to radius); null: the active point scalars
   * when VaryRadius is not off. Default null.
   */
  vtkSetStringMacro(RadiusArrayName);
  vtkGetStringMacro(RadiusArrayName);

  enum VaryRadiusModes
  {
    VARY_RADIUS_OFF = 0,
    VARY_RADIUS_BY_SCALAR,
    VARY_RADIUS_BY_ABSOLUTE_SCALAR
  };

  /**
   * How the radius array sets the radius (vtkTubeFilter's modes). Default
   * VARY_RADIUS_BY_ABSOLUTE_SCALAR when RadiusArrayName is set, else VARY_RADIUS_OFF.
   */
  vtkSetClampMacro(VaryRadius, int, VARY_RADIUS_OFF, VARY_RADIUS_BY_ABSOLUTE_SCALAR);
  void SetVaryRadiusToVaryRadiusOff() { this->SetVaryRadius(VARY_RADIUS_OFF); }
  void SetVaryRadiusToVaryRadiusByScalar() { this->SetVaryRadius(VARY_RADIUS_BY_SCALAR); }
  void SetVaryRadiusToVaryRadiusByAbsoluteScalar()
  {
    this->SetVaryRadius(VARY_RADIUS_BY_ABSOLUTE_SCALAR);
  }
  int GetVaryRadius();

  /**
   * VARY_RADIUS_BY_ABSOLUTE_SCALAR: factor on the array's values. Default 1.
   */
  vtkSetMacro(RadiusScale, double);
  vtkGetMacro(RadiusScale, double);

  /**
   * VARY_RADIUS_BY_SCALAR: largest radius over Radius. Default 10 (as vtkTubeFilter).
   */
  vtkSetMacro(RadiusFactor, double);
  vtkGetMacro(RadiusFactor, double);

  /**
   * Point array of predecessor indices (-1: none) instead of the polylines. Default null.
   */
  vtkSetStringMacro(PredecessorArrayName);
  vtkGetStringMacro(PredecessorArrayName);

  enum LinkLayouts
  {
    LINKS_COMBINED_ON_THE_FLY = 0,
    LINKS_COMBINED_PRECOMPUTED,
    LINKS_SEPARATE_ON_THE_FLY,
    LINKS_SEPARATE_PRECOMPUTED,
    LINKS_CHUNKED,  ///< up to ChunkLinks consecutive links of a tube per BVH primitive
    LINKS_AUTOMATIC ///< LINKS_CHUNKED from AutomaticChunkedLinks points, else combined
  };

  /**
   * Control points from which LINKS_AUTOMATIC takes chunks. Default 10,000,000: there the
   * combined layout holds about 1.1 GB and chunks save about 0.85 GB, at frames about 1.8
   * times slower (1M-link benchmark); below, speed wins.
   */
  vtkSetClampMacro(AutomaticChunkedLinks, vtkIdType, 0, VTK_ID_MAX);
  vtkGetMacro(AutomaticChunkedLinks, vtkIdType);

  ///@{
  /**
   * The most links a chunk holds (LINKS_CHUNKED). Default 0, automatic: 8 below
   * AutomaticLongChunkLinks control points, 16 from there. Measured on a whole-brain
   * tractogram of 10^7 links (Benchmarks/whole_brain.py): 8 links take 11.2 bytes per link
   * plus 9.3 of BVH, 16 take 8.8 plus 4.9 at opaque frames 2.2 times as long, which a
   * tractogram of 10^9 links needs to fit in 20 GB.
   */
  vtkSetClampMacro(ChunkLinks, int, 0, 64);
  vtkGetMacro(ChunkLinks, int);
  vtkSetClampMacro(AutomaticLongChunkLinks, vtkIdType, 0, VTK_ID_MAX);
  vtkGetMacro(AutomaticLongChunkLinks, vtkIdType);
  ///@}

  /**
   * The most links a chunk held in the last chunked build (ChunkLinks resolved), 0 before any.
   */
  vtkGetMacro(BuiltChunkLinks, int);

  ///@{
  /**
   * The link primitive: a link's sphere and cone stump as one BVH primitive or two, or a run
   * of links as one, and the stump's parameters stored or computed at every ray test. The
   * numbers of the first four stay as they were. Default LINKS_AUTOMATIC.
   */
  vtkSetClampMacro(LinkLayout, int, LINKS_COMBINED_ON_THE_FLY, LINKS_AUTOMATIC);
  vtkGetMacro(LinkLayout, int);
  const char* GetLinkLayoutAsString();
  ///@}

  /**
   * Pieces to pull the input in (see the class comment). Default 1: the input is updated and
   * drawn whole. Above 1 the tubes are always chunked (LinkLayout LINKS_AUTOMATIC or
   * LINKS_CHUNKED; another layout is an error), from polylines (not PredecessorArrayName), with
   * a constant radius or VARY_RADIUS_BY_ABSOLUTE_SCALAR (the range VARY_RADIUS_BY_SCALAR needs
   * is the whole input's); colours come from the mapper's scalar range (set it, or the lookup
   * table's with UseLookupTableScalarRange, to the whole input's range). Picks name cell and
   * point ids of the whole input as pieces that number their cells and points in turn give it
   * (as the readers above do).
   */
  vtkSetClampMacro(StreamedPieces, int, 1, VTK_INT_MAX);
  vtkGetMacro(StreamedPieces, int);

  ///@{
  /**
   * Hidden-link culling (chunked layouts): where tubes fill their bounds many times over (a
   * whole-brain tractogram of 10^9 links), links that lie inside other links' solids are left
   * out of opaque frames and picks seen from outside the tubes' bounds. Such frames are
   * exactly the same (a ray from outside first meets the union's surface, which no hidden link
   * reaches); translucent frames, views from inside the bounds and a clipping Region trace every
   * link (their BVH is then built on first use). A pass over the links decides it, and runs only
   * where tubes fill their bounding box 50 times over (sightline::outerLinks); it reports
   * progress (ProgressEvent, progress text "finding hidden links"). Default on.
   */
  vtkSetMacro(HiddenLinkCulling, vtkTypeBool);
  vtkGetMacro(HiddenLinkCulling, vtkTypeBool);
  vtkBooleanMacro(HiddenLinkCulling, vtkTypeBool);
  ///@}

  /**
   * Links the last build found hidden (0 where it culled none).
   */
  vtkGetMacro(HiddenLinks, vtkIdType);

  /**
   * Seconds the last build spent deciding which links are hidden (part of
   * GetLastGeometrySeconds(); 0 where the pass did not run): of which marking covered voxels,
   * and testing each link against them. What is left of the geometry time is reading the input
   * and building the tubes.
   */
  vtkGetMacro(LastCullingSeconds, double);
  vtkGetMacro(LastCullingMarkSeconds, double);
  vtkGetMacro(LastCullingTestSeconds, double);

  /**
   * The layout the last build used (LINKS_AUTOMATIC resolved), -1 before any.
   */
  vtkGetMacro(BuiltLinkLayout, int);

  /**
   * Control points of the last build (each with its link to a predecessor, if any).
   */
  vtkGetMacro(NumberOfLinks, vtkIdType);

  /**
   * The largest radius these settings give a point of `data` (see vtkSightlineMapper).
   */
  double ComputeReach(vtkDataObject* data) override;

protected:
  vtkSightlineTubeMapper();
  ~vtkSightlineTubeMapper() override;

  const char* GetDrawnInputType() override { return "vtkPointSet"; }
  bool AppendsCompositeLeaves() override { return true; }
  bool PullsInputPieces() override;
#ifndef __VTK_WRAP__
  std::shared_ptr<sightline::Geometry> BuildGeometry() override;
  /**
   * BuildGeometry() with StreamedPieces above 1.
   */
  std::shared_ptr<sightline::Geometry> BuildStreamedGeometry();
  std::shared_ptr<sightline::Geometry> BuildOuterGeometry(const sightline::Geometry& whole) override;
  /**
   * The radius of each point of `input` (false after an error naming the problem).
   */
  bool ComputePointRadii(vtkPointSet* input, std::vector<float>& radius);
  /**
   * Selection: a link (its cone stump and end sphere) is picked as the point it starts from
   * (its predecessor; a tube's first sphere as its own point) and as the polyline cell it
   * belongs to (none with PredecessorArrayName).
   */
  void ComputeSelectionIds(
    std::vector<vtkIdType>& pointIds, std::vector<vtkIdType>& cellIds) override;
#endif
  bool SupportsTranslucency() override { return true; }

  double Radius = 1.0;
  char* RadiusArrayName = nullptr;
  int VaryRadius = -1; ///< -1: by the array when one is named
  double RadiusScale = 1.0;
  double RadiusFactor = 10.0;
  char* PredecessorArrayName = nullptr;
  int LinkLayout = LINKS_AUTOMATIC;
  int BuiltLinkLayout = -1;
  vtkIdType AutomaticChunkedLinks = 10000000;
  int ChunkLinks = 0;
  vtkIdType AutomaticLongChunkLinks = 100000000;
  int BuiltChunkLinks = 0;
  /// ChunkLinks, or the automatic choice for a build of `points` control points.
  unsigned ChunkLinksFor(double points) const;
  vtkIdType NumberOfLinks = 0;
  int StreamedPieces = 1;
  vtkTypeBool HiddenLinkCulling = 1;
  vtkIdType HiddenLinks = 0;
  double LastCullingSeconds = 0.0;
  double LastCullingMarkSeconds = 0.0;
  double LastCullingTestSeconds = 0.0;

#ifndef __VTK_WRAP__
  /**
   * A streamed build's tubes, one per polyline kept: the index of its first control point
   * among those given to the builder, its cell id and the id of its first point in the whole
   * input (-1 when the polyline's point ids do not follow each other).
   */
  struct StreamedRuns
  {
    std::vector<std::uint32_t> FirstControlPoint;
    std::vector<vtkIdType> Cell;
    std::vector<vtkIdType> FirstPoint;
  } Streamed;
#endif

private:
  vtkSightlineTubeMapper(const vtkSightlineTubeMapper&) = delete;
  void operator=(const vtkSightlineTubeMapper&) = delete;
};

#endif
