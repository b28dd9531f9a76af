// SPDX-License-Identifier: BSD-3-Clause
/**
 * @class   vtkSightlineTrackVisReader
 * @brief   Reads TrackVis streamlines (.trk, versions 1 and 2) into vtkPolyData polylines.
 *
 * The 1000-byte header gives the voxel size, the voxel order (e.g. "LAS"), the voxel-to-RAS
 * matrix (version 2) and the names of per-point scalars and per-streamline properties; each
 * streamline is a point count, the points (x y z and the scalars) and the properties. Both
 * byte orders are read (the header size, 1000, tells which).
 *
 * TrackVis stores points in "voxmm" (voxel coordinates times the voxel size, origin at the
 * corner of the first voxel). By default they are mapped to RAS mm the way nibabel and DIPY
 * do: to voxel centres, through the flips between the header's voxel order and the matrix's
 * orientation, then through the voxel-to-RAS matrix (identity when the file has none, voxel
 * order LPS when it has none, TrackVis' defaults). CoordinatesVoxmm keeps the raw values.
 *
 * Output: one polyline per streamline; per-point scalars and per-cell properties as arrays
 * named from the header ("scalar_<i>" / "property_<i>" when unnamed; a name "NAME\0COUNT", as
 * nibabel writes vectors such as colours, is one array of COUNT components). Errors: a missing file,
 * no "TRACK" id, a header size that is not 1000 in either byte order, a negative point count,
 * and (when mapping to RAS) a voxel order that names an axis twice (e.g. "RAR") or a
 * voxel-to-RAS matrix that is not finite and invertible. Warnings: a file cut inside a
 * streamline (the complete ones are kept); streamlines with NaN or infinite coordinates
 * (left out, the first one named). Text quoted from the file is escaped to printable UTF-8.
 *
 * Pieces (pvbatch/pvserver ranks): the reader takes piece requests (CAN_HANDLE_PIECE_REQUEST).
 * Piece p of n gets streamlines [p N / n, (p + 1) N / n) of the file's N, in file order, with
 * their scalars and properties, the last piece also any beyond N; N is the header's n_count,
 * or, when it is 0 (unknown), counted by a scan that reads only the point counts and seeks
 * past the points. The streamlines before the piece are skipped the same way, so a piece reads
 * and holds only its own points (about 1/n). Piece 0 of 1 is the whole file. The end-of-file
 * warnings (cut short, an n_count that disagrees) come from the piece that reads to the end.
 */
#ifndef vtkSightlineTrackVisReader_h
#define vtkSightlineTrackVisReader_h

#include "SightlineIOModule.h" // for export macro
#include "vtkNew.h"            // for vtkNew
#include "vtkPolyDataAlgorithm.h"

#include <string> // for std::string

class vtkMatrix4x4;

class SIGHTLINEIO_EXPORT vtkSightlineTrackVisReader : public vtkPolyDataAlgorithm
{
public:
  static vtkSightlineTrackVisReader* New();
  vtkTypeMacro(vtkSightlineTrackVisReader, vtkPolyDataAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  vtkSetStringMacro(FileName);
  vtkGetStringMacro(FileName);

  ///@{
  /**
   * With ReadFromInputString on, the reader parses InputString (the bytes of a whole .trk
   * file) instead of FileName.
   */
  void SetInputString(const std::string& bytes);
  const std::string& GetInputString() const { return this->InputString; }
  vtkSetMacro(ReadFromInputString, bool);
  vtkGetMacro(ReadFromInputString, bool);
  vtkBooleanMacro(ReadFromInputString, bool);
  ///@}

  /**
   * Keep TrackVis' voxmm coordinates instead of mapping them to RAS mm. Default off.
   */
  vtkSetMacro(CoordinatesVoxmm, bool);
  vtkGetMacro(CoordinatesVoxmm, bool);
  vtkBooleanMacro(CoordinatesVoxmm, bool);

  /**
   * The map from voxmm to RAS mm of the last read (identity before the first).
   */
  vtkMatrix4x4* GetVoxmmToRASMatrix() { return this->VoxmmToRAS; }

  /**
   * The header's voxel order of the last read (e.g. "LAS").
   */
  const char* GetVoxelOrder() { return this->VoxelOrder; }

  static int CanReadFile(const char* fileName);

protected:
  vtkSightlineTrackVisReader();
  ~vtkSightlineTrackVisReader() override;

  int RequestInformation(vtkInformation* request, vtkInformationVector** inputVector,
    vtkInformationVector* outputVector) override;
  int RequestData(vtkInformation* request, vtkInformationVector** inputVector,
    vtkInformationVector* outputVector) override;

  char* FileName = nullptr;
  std::string InputString;
  bool ReadFromInputString = false;
  bool CoordinatesVoxmm = false;
  vtkNew<vtkMatrix4x4> VoxmmToRAS;
  char VoxelOrder[4] = { 0, 0, 0, 0 };

private:
  vtkSightlineTrackVisReader(const vtkSightlineTrackVisReader&) = delete;
  void operator=(const vtkSightlineTrackVisReader&) = delete;
};

#endif
