// SPDX-License-Identifier: BSD-3-Clause
/**
 * @class   vtkSightlineSphericalVolumeMapper
 * @brief   Volume mapper that ray-casts spherical grids (r, theta, phi), and cylindrical ones,
 *          natively, cell by cell.
 *
 * The input is a vtkRectilinearGrid whose x, y and z coordinates are the radius r, the polar
 * angle and the azimuth phi of a spherical grid (breakpoints may be non-uniform; a section,
 * e.g. a shell, a wedge or a cap, is drawn as such). Every pixel's ray is traversed exactly
 * through the grid's cells (sightline::SphericalTraversal, after "Ray casting in spherical
 * coordinates"): no resampling to a Cartesian image, so layer boundaries stay spheres and
 * cones at any zoom.
 *
 * Cylindrical grids (SetCoordinateSystemToCylindrical) are read as x = rho (the distance from
 * the z axis), y = azimuth (AngleUnits apply), z = height, and traversed by the same scheme
 * (sightline::CylindricalTraversal).
 *
 * Convention (see SetAngleUnits, SetPolarAngle):
 * - x: radius r >= 0, in world units (the vtkVolume's matrix places and scales it);
 * - y: colatitude theta in [0, pi] from +z (default), or latitude in [-pi/2, pi/2];
 * - z: azimuth phi from +x towards +y, spanning at most 2 pi;
 * - angles in radians (default) or degrees;
 * - scalars: cell data is constant per cell (composited exactly); point data is interpolated
 *   trilinearly inside the cells and sampled (see InterpolatePointData, SampleDistance). The
 *   first component is used. ScalarMode / SelectScalarArray choose the array
 *   as in other volume mappers.
 *
 * Rendering: emission-absorption through the vtkVolumeProperty's colour transfer function and
 * scalar opacity (component 0); an opacity a per ScalarOpacityUnitDistance u is the extinction
 * -ln(1 - a) / u, integrated exactly over each cell's length. Cells whose opacity is zero are
 * skipped, and rays stop once the remaining transmittance is below MinimumTransmittance. With
 * shading on (vtkVolumeProperty::ShadeOn) each cell is lit as a surface whose normal is the
 * field's gradient (central differences between neighbouring cells), with the property's
 * ambient, diffuse, specular and specular power and the renderer's lights. Only COMPOSITE_BLEND
 * is supported; gradient opacity and cropping are ignored.
 *
 * In a window the mapper is drawn in VTK's volumetric pass: it reads the depth of the
 * geometry drawn before it (a coastline, a core sphere) and stops rays there, then blends its
 * premultiplied image over the frame and writes the depth where each ray entered its first
 * visible cell. While the window asks for an interactive rate it traces every
 * InteractiveSubsampling-th pixel. RayTrace() is the GL-free path (vtkSightlineImageRenderer).
 *
 * Bad input (non-monotonic coordinates, r < 0, polar angles outside their range, an azimuth
 * span over 2 pi, missing scalars, a wrong number of values) is reported with vtkErrorMacro and
 * nothing is drawn. NaN scalars are treated as empty cells (with a warning). No input or a
 * grid without points draws nothing, quietly, and GetBounds() is then uninitialized.
 *
 * Composite input (vtkMultiBlockDataSet, vtkPartitionedDataSet(Collection), as ParaView
 * passes): its one non-empty vtkRectilinearGrid leaf is drawn; with several, the first, with a
 * warning naming their count; leaves of another type are left out with an error.
 *
 * Selection: the volume cannot be picked. In vtkHardwareSelector's passes it draws nothing
 * (neither ids nor depth), so it neither is selected nor hides what is behind it, as VTK's
 * own volume mappers.
 *
 * @sa vtkSightlineSphericalFieldSource vtkSightlineMapper vtkFixedPointVolumeRayCastMapper
 */
#ifndef vtkSightlineSphericalVolumeMapper_h
#define vtkSightlineSphericalVolumeMapper_h

#include "SightlineRenderingModule.h" // for export macro
#include "SightlineTracer.h"          // for the interface the window frame and image renderer use
#include "vtkVolumeMapper.h"

#ifndef __VTK_WRAP__
#include <memory> // for std::unique_ptr
#include <vector> // for std::vector
namespace sightline
{
class Framebuffer;
class SphericalTraversal;
struct SphericalGrid;
struct CylindricalGrid;
}
#endif

class vtkCamera;
class vtkLightCollection;
class vtkRectilinearGrid;

class SIGHTLINERENDERING_EXPORT vtkSightlineSphericalVolumeMapper
  : public vtkVolumeMapper
  , public SightlineTracer
{
public:
  static vtkSightlineSphericalVolumeMapper* New();
  vtkTypeMacro(vtkSightlineSphericalVolumeMapper, vtkVolumeMapper);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  enum CoordinateSystems
  {
    SPHERICAL = 0, ///< x = r, y = polar angle, z = azimuth
    CYLINDRICAL    ///< x = rho (distance from the z axis), y = azimuth, z = height
  };

  ///@{
  /**
   * How the input's coordinates are read. Default SPHERICAL.
   */
  vtkSetClampMacro(CoordinateSystem, int, SPHERICAL, CYLINDRICAL);
  vtkGetMacro(CoordinateSystem, int);
  void SetCoordinateSystemToSpherical() { this->SetCoordinateSystem(SPHERICAL); }
  void SetCoordinateSystemToCylindrical() { this->SetCoordinateSystem(CYLINDRICAL); }
  ///@}

  enum AngleUnit
  {
    RADIANS = 0,
    DEGREES
  };
  enum PolarAngleKind
  {
    COLATITUDE = 0, ///< 0 at the north pole (+z), pi at the south pole
    LATITUDE        ///< pi/2 at the north pole, -pi/2 at the south pole
  };

  ///@{
  /**
   * Units of the y (polar) and z (azimuth) coordinates. Default RADIANS.
   */
  vtkSetClampMacro(AngleUnits, int, RADIANS, DEGREES);
  vtkGetMacro(AngleUnits, int);
  void SetAngleUnitsToRadians() { this->SetAngleUnits(RADIANS); }
  void SetAngleUnitsToDegrees() { this->SetAngleUnits(DEGREES); }
  ///@}

  ///@{
  /**
   * Meaning of the y coordinate. Default COLATITUDE.
   */
  vtkSetClampMacro(PolarAngle, int, COLATITUDE, LATITUDE);
  vtkGetMacro(PolarAngle, int);
  void SetPolarAngleToColatitude() { this->SetPolarAngle(COLATITUDE); }
  void SetPolarAngleToLatitude() { this->SetPolarAngle(LATITUDE); }
  ///@}

  ///@{
  /**
   * Point data is interpolated trilinearly in the grid's coordinates inside each cell and
   * composited with samples at most SampleDistance apart along each cell segment (default on;
   * off: each cell takes the mean of its corners and is composited exactly). With shading on,
   * point data is averaged per cell (shading is per cell).
   */
  vtkSetMacro(InterpolatePointData, vtkTypeBool);
  vtkGetMacro(InterpolatePointData, vtkTypeBool);
  vtkBooleanMacro(InterpolatePointData, vtkTypeBool);
  ///@}

  ///@{
  /**
   * Largest distance between samples for interpolated point data, in the grid's units;
   * 0 (default) means half the thinnest radial cell.
   */
  vtkSetClampMacro(SampleDistance, double, 0.0, VTK_DOUBLE_MAX);
  vtkGetMacro(SampleDistance, double);
  ///@}

  ///@{
  /**
   * Rays stop once the light they still let through falls below this (early ray
   * termination). Default 0.002 (one 8-bit level).
   */
  vtkSetClampMacro(MinimumTransmittance, double, 0.0, 1.0);
  vtkGetMacro(MinimumTransmittance, double);
  ///@}

  ///@{
  /**
   * Pixel step (clamped to [1, 16]; 1 disables subsampling) while the render window asks for
   * an interactive frame rate above InteractiveUpdateRate. Defaults 2 and 1 frame per second,
   * as vtkSightlineMapper.
   */
  void SetInteractiveSubsampling(int step);
  int GetInteractiveSubsampling();
  void SetInteractiveUpdateRate(double rate);
  double GetInteractiveUpdateRate();
  ///@}

  ///@{
  /**
   * The box of world space this mapper draws: xmin, xmax, ymin, ymax, zmin, zmax, faces
   * possibly infinite. Every ray is clipped to it, so that each MPI rank draws only its region
   * of a partition and the ranks' images, blended front to back in the regions' visibility
   * order, give the one-process image (vtkSightlineSphericalVolumeRepresentation sets it under
   * ParaView's ordered compositing). Default: all of space. A NaN or a min above its max is an
   * error, and nothing is drawn.
   */
  vtkSetVector6Macro(Region, double);
  vtkGetVector6Macro(Region, double);
  void SetRegionToAllOfSpace();
  ///@}

  /**
   * The box (xmin, xmax, ymin, ymax, zmin, zmax) around the section that `grid`'s coordinates
   * describe with this mapper's settings (CoordinateSystem, AngleUnits, PolarAngle), in the
   * grid's own coordinates; only the coordinates are read. False, after an error naming the
   * problem, when they are no such grid.
   */
  bool ComputeSectionBounds(vtkRectilinearGrid* grid, double bounds[6]);

  /**
   * The cells of `grid` (read as ComputeSectionBounds does) that may meet `box` (in the grid's
   * own coordinates), as inclusive ranges of cell indices along the grid's x, y and z:
   * cellRange = { i0, i1, j0, j1, k0, k1 }. A superset (from the ranges of r, theta and phi, or
   * rho, phi and z, over the box), so that a rank drawing `box` needs no other cell. False when
   * no cell can meet the box, or after an error for a grid that is no such grid. On a full
   * circle the azimuth range (z for spherical grids, y for cylindrical ones) may run across
   * the seam: then its first index is greater than its last, meaning cells first..n-1 followed
   * by 0..last (a grid of those cells goes on past the seam: its azimuths after it are the
   * grid's plus one turn, 360 degrees or 2 pi). `margin` widens the ranges by that many cells on
   * each side (within the grid, or around a full circle): the neighbours that shading's
   * gradients read.
   */
  bool ComputeCellRangeInBox(vtkRectilinearGrid* grid, const double box[6], int cellRange[6], int margin = 0);

  /**
   * Seconds the last frame took, and the cell segments it composited.
   */
  vtkGetMacro(LastFrameSeconds, double);
  vtkGetMacro(LastCellsVisited, vtkIdType);

  /**
   * Ray-cast the volume and draw it into the current viewport (volumetric pass).
   */
  void Render(vtkRenderer* renderer, vtkVolume* volume) override;

#ifndef __VTK_WRAP__
  /**
   * GL-free path: ray-cast `volume` (a vtkVolume) as `camera` sees it into a width x height
   * framebuffer (colour not premultiplied, depth of the first visible cell), stopping rays at
   * `depthLimit` (window depths, bottom row first) when given. Returns false after reporting
   * an error when nothing could be rendered. The window path uses this same function.
   */
  bool RayTrace(vtkProp3D* volume, vtkCamera* camera, vtkLightCollection* lights, int width,
    int height, sightline::Framebuffer& framebuffer,
    const std::vector<float>* depthLimit = nullptr) override;
#endif

  void ReleaseGraphicsResources(vtkWindow* window) override;

  /**
   * World-space bounds of the grid's section (a box around the ball of its largest radius,
   * tightened where the angles allow), not of its (r, theta, phi) coordinates.
   */
  double* GetBounds() VTK_SIZEHINT(6) override;
  using vtkAbstractMapper3D::GetBounds;

protected:
  vtkSightlineSphericalVolumeMapper();
  ~vtkSightlineSphericalVolumeMapper() override;

  int FillInputPortInformation(int port, vtkInformation* info) override;

  int CoordinateSystem = SPHERICAL;
  vtkTypeBool InterpolatePointData = 1;
  double SampleDistance = 0.0;
  int AngleUnits = RADIANS;
  int PolarAngle = COLATITUDE;
  double MinimumTransmittance = 0.002;
  double Region[6];
  double LastFrameSeconds = 0.0;
  vtkIdType LastCellsVisited = 0;

private:
  vtkSightlineSphericalVolumeMapper(const vtkSightlineSphericalVolumeMapper&) = delete;
  void operator=(const vtkSightlineSphericalVolumeMapper&) = delete;

  // Half the thinnest radial cell, when SampleDistance is 0.
  double AutomaticSampleDistance();

#ifndef __VTK_WRAP__
  // The input's coordinates as a kernel grid of the kind CoordinateSystem says (the other is
  // left empty); false after an error naming what is wrong.
  bool ReadCoordinates(
    vtkRectilinearGrid* input, sightline::SphericalGrid& sphere, sightline::CylindricalGrid& cylinder);
#endif

#ifndef __VTK_WRAP__
  // SightlineTracer, for the window frame and vtkSightlineImageRenderer.
  Pass GetPass(vtkProp3D*) override { return Pass::Volumetric; }
  // Brings the kernel grid and cell values up to date with the input; false when there is
  // nothing to draw (after an error, unless the input is empty).
  bool UpdateScene() override;
  vtkMTimeType GetSceneTime() override;
#endif

  class vtkInternals;
  std::unique_ptr<vtkInternals> Internals;
};

#endif
