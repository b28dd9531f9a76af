// SPDX-License-Identifier: BSD-3-Clause
/**
 * @class   vtkSightlineTCKReader
 * @brief   Reads MRtrix3 track files (.tck) into vtkPolyData polylines.
 *
 * A .tck file is a text header (`mrtrix tracks`, `key: value` lines, `END`) whose `file: .
 * OFFSET` entry locates the data: float32 or float64 triplets in little or big endian
 * (`datatype` Float32LE, Float32BE, Float64LE, Float64BE), each streamline ended by a NaN
 * triplet and the file by an Inf triplet. Points are scanner coordinates in mm (RAS), as
 * MRtrix3 writes them; one polyline per streamline.
 *
 * A file cut short (no Inf triplet) keeps its complete streamlines, with a warning (the points
 * of an incomplete last one are dropped with it); a `count` that disagrees with the
 * streamlines read is reported as a warning too, and so are streamlines with a coordinate
 * beyond single precision (a Float64 file), which are left out. A missing file, a wrong first
 * line, a header without END, `file` or a known `datatype`, or a data offset inside the header
 * or beyond the file are errors. Text quoted from the file in messages is escaped to printable
 * UTF-8.
 *
 * Pieces (pvbatch/pvserver ranks): the reader takes piece requests (CAN_HANDLE_PIECE_REQUEST).
 * Piece p of n gets streamlines [p N / n, (p + 1) N / n) of the file's N, in file order, the
 * last piece also any beyond N; N is the header's `count`, or, without one, found by a first
 * pass that only counts NaN triplets. The file is read a chunk at a time and only the
 * piece's points are stored, so a piece holds about 1/n of the points (the streamlines before
 * it are scanned, not kept). Piece 0 of 1 is the whole file. The end-of-file warnings (no end
 * marker, a count that disagrees) come from the piece that reads to the end.
 *
 * Track scalars: ScalarFileName names an MRtrix3 track scalar file (.tsf, as `tcksample`
 * writes) for the same tracks; its values become a float point-data array named after the file
 * (without .tsf), for the piece's tracks only. A track whose value count differs from its point
 * count, or a .tsf with fewer tracks, is an error.
 */
#ifndef vtkSightlineTCKReader_h
#define vtkSightlineTCKReader_h

#include "SightlineIOModule.h" // for export macro
#include "vtkPolyDataAlgorithm.h"

#include <string> // for std::string

class SIGHTLINEIO_EXPORT vtkSightlineTCKReader : public vtkPolyDataAlgorithm
{
public:
  static vtkSightlineTCKReader* New();
  vtkTypeMacro(vtkSightlineTCKReader, vtkPolyDataAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  vtkSetStringMacro(FileName);
  vtkGetStringMacro(FileName);

  ///@{
  /** An MRtrix3 track scalar file (.tsf) whose values become point data (none: empty). */
  vtkSetStringMacro(ScalarFileName);
  vtkGetStringMacro(ScalarFileName);
  ///@}

  ///@{
  /**
   * With ReadFromInputString on, the reader parses InputString (the bytes of a whole .tck
   * file) instead of FileName.
   */
  void SetInputString(const std::string& bytes);
  const std::string& GetInputString() const { return this->InputString; }
  vtkSetMacro(ReadFromInputString, bool);
  vtkGetMacro(ReadFromInputString, bool);
  vtkBooleanMacro(ReadFromInputString, bool);
  ///@}

  /**
   * Whether the file starts like a .tck file.
   */
  static int CanReadFile(const char* fileName);

protected:
  vtkSightlineTCKReader();
  ~vtkSightlineTCKReader() override;

  int RequestInformation(vtkInformation* request, vtkInformationVector** inputVector,
    vtkInformationVector* outputVector) override;
  int RequestData(vtkInformation* request, vtkInformationVector** inputVector,
    vtkInformationVector* outputVector) override;

  char* FileName = nullptr;
  char* ScalarFileName = nullptr;
  std::string InputString;
  bool ReadFromInputString = false;

private:
  vtkSightlineTCKReader(const vtkSightlineTCKReader&) = delete;
  void operator=(const vtkSightlineTCKReader&) = delete;
};

#endif
