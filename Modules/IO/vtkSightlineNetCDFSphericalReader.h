// SPDX-License-Identifier: BSD-3-Clause
/**
 * @class   vtkSightlineNetCDFSphericalReader
 * @brief   Reads CF netCDF longitude/latitude/vertical grids (Earth and planetary models) as
 *          spherical (r, theta, phi) grids for vtkSightlineSphericalVolumeMapper, without
 *          resampling.
 *
 * The file is netCDF (classic, 64-bit offset or netCDF-4) following the CF conventions, as
 * IRIS's Earth Model Collection distributes seismic tomography models: variables over a
 * longitude (units degrees_east), a latitude (degrees_north; or a colatitude) and a vertical
 * coordinate, in any order, plus optional dimensions of length one (e.g. time). Every such
 * variable over the same three axes becomes a point-data array (values at the grid's nodes);
 * VariableName picks the active scalars (default: the first).
 *
 * The output is a vtkRectilinearGrid in the mapper's default convention, so nothing needs
 * setting on the mapper:
 * - x: radius in km. The vertical coordinate is a depth (positive down) below
 *   ReferenceRadius (6371 km), a radius, or an altitude above ReferenceRadius, in m or km (its
 *   `units`); which one comes from its `positive` attribute and names (see
 *   VerticalCoordinate);
 * - y: colatitude in radians, 0 at the north pole;
 * - z: azimuth (longitude) in radians, east of the prime meridian. [-180, 180) and [0, 360)
 *   longitudes are both read; a regional grid crossing the 180-degree meridian (170, 180,
 *   -170) is unwrapped into one increasing run; a global grid without its closing meridian
 *   (0, 1, ..., 359) gets one (the first meridian's values again), so that it closes.
 * Every axis is written increasing, whatever order the file stores (e.g. latitude from north
 * to south, depth increasing = radius decreasing); the values follow their nodes.
 *
 * The field data holds "ReferenceRadius" (km), the radius depths were measured from, for
 * whatever is drawn with the model (a graticule, stations).
 *
 * Values: `scale_factor` and `add_offset` are applied; `_FillValue` (or netCDF's default fill
 * without one) and `missing_value` become NaN, which the mapper draws as empty cells. double
 * variables stay double, all others become float.
 *
 * Errors name the file and the coordinate: no variable over a longitude, a latitude and a
 * vertical axis; an axis that is not strictly monotonic, has fewer than two nodes or
 * non-finite values; a vertical coordinate without length units or whose kind cannot be told;
 * a depth beyond the reference radius; a latitude beyond a pole; longitudes going round more
 * than once; a variable larger than the file could hold; files netCDF cannot open.
 *
 * Pieces: the reader produces any sub-extent (what pvbatch/pvserver ranks ask for) and reads
 * only the nodes it needs from the file.
 *
 * @sa vtkSightlineSphericalVolumeMapper vtkNetCDFCFReader
 */
#ifndef vtkSightlineNetCDFSphericalReader_h
#define vtkSightlineNetCDFSphericalReader_h

#include "SightlineIOModule.h" // for export macro
#include "vtkRectilinearGridAlgorithm.h"

#include <memory> // for std::unique_ptr
#include <string> // for std::string

class SIGHTLINEIO_EXPORT vtkSightlineNetCDFSphericalReader : public vtkRectilinearGridAlgorithm
{
public:
  static vtkSightlineNetCDFSphericalReader* New();
  vtkTypeMacro(vtkSightlineNetCDFSphericalReader, vtkRectilinearGridAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  vtkSetStringMacro(FileName);
  vtkGetStringMacro(FileName);

  ///@{
  /**
   * The variable that becomes the active scalars (none or empty: the first over the grid's
   * axes). A name that is not such a variable is an error.
   */
  vtkSetStringMacro(VariableName);
  vtkGetStringMacro(VariableName);
  ///@}

  ///@{
  /** The radius the depth (or altitude) is measured from, in km. Default 6371 (the Earth). */
  vtkSetClampMacro(ReferenceRadius, double, 0.0, VTK_DOUBLE_MAX);
  vtkGetMacro(ReferenceRadius, double);
  ///@}

  enum VerticalCoordinates
  {
    AUTOMATIC = 0, ///< from `positive` (down: depth, up: altitude) and the names ("radius")
    DEPTH,         ///< below ReferenceRadius
    RADIUS,        ///< from the centre
    ALTITUDE       ///< above ReferenceRadius
  };

  ///@{
  /** How the vertical coordinate is read. Default AUTOMATIC. */
  vtkSetClampMacro(VerticalCoordinate, int, AUTOMATIC, ALTITUDE);
  vtkGetMacro(VerticalCoordinate, int);
  ///@}

  ///@{
  /**
   * After UpdateInformation(): the variables over the grid's axes, in file order (the
   * variables of the first such grid when VariableName is unset).
   */
  int GetNumberOfVariables();
  const char* GetVariableNameOf(int index);
  ///@}

  ///@{
  /**
   * With ReadFromInputString on, the reader parses InputString (the bytes of a whole netCDF
   * file) instead of FileName.
   */
  void SetInputString(const std::string& bytes);
  const std::string& GetInputString() const;
  vtkSetMacro(ReadFromInputString, bool);
  vtkGetMacro(ReadFromInputString, bool);
  vtkBooleanMacro(ReadFromInputString, bool);
  ///@}

  /**
   * Whether netCDF opens the file and it has a variable over a longitude, a latitude and a
   * vertical axis.
   */
  static int CanReadFile(const char* fileName);

protected:
  vtkSightlineNetCDFSphericalReader();
  ~vtkSightlineNetCDFSphericalReader() override;

  int RequestInformation(vtkInformation* request, vtkInformationVector** inputVector,
    vtkInformationVector* outputVector) override;
  int RequestData(vtkInformation* request, vtkInformationVector** inputVector,
    vtkInformationVector* outputVector) override;

private:
  vtkSightlineNetCDFSphericalReader(const vtkSightlineNetCDFSphericalReader&) = delete;
  void operator=(const vtkSightlineNetCDFSphericalReader&) = delete;

  char* FileName = nullptr;
  char* VariableName = nullptr;
  double ReferenceRadius = 6371.0;
  int VerticalCoordinate = AUTOMATIC;
  bool ReadFromInputString = false;

  struct Internals;
  std::unique_ptr<Internals> Internal;
};

#endif
