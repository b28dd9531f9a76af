// SPDX-License-Identifier: BSD-3-Clause
/**
 * @class   vtkSightlineTRXReader
 * @brief   Reads TRX tractograms (.trx archives or their directory form) into vtkPolyData.
 *
 * TRX (tee-ar-ex/trx-spec; DIPY's default tractogram format) is a zip archive, stored or
 * deflated, or a directory holding the same members:
 * - `header.json`: `NB_VERTICES`, `NB_STREAMLINES`, `VOXEL_TO_RASMM` (4x4), `DIMENSIONS` (3);
 * - `positions.3.{float16,float32,float64}`: the vertices, in RAS mm;
 * - `offsets.{uint32,uint64}` (any integer dtype is read): where each streamline starts, one
 *   per streamline in older files, one more (equal to NB_VERTICES) in current trx-python's;
 * - `dpv/NAME[.COLUMNS].DTYPE`, `dps/...`: data per vertex and per streamline;
 * - `groups/NAME.DTYPE`: streamline indices; `dpg/GROUP/NAME...`: data per group.
 *
 * Output: one polyline per streamline, in file order. Streamlines of fewer than two vertices,
 * which a vtkPolyData line cannot be, are left out with a warning (with their dps rows and group
 * memberships; their vertices stay, unused, so that dpv stays whole). Points are float for float16 and float32 positions
 * (float16 converts exactly) and double for float64. dpv become point data and dps cell data, of
 * the member's dtype (float16 as float, bit as unsigned char); each group becomes a cell-data
 * unsigned char array `group:NAME` (1 for its streamlines); dpg become field data
 * `dpg:GROUP:NAME`; the header's matrix and dimensions become field data `VOXEL_TO_RASMM` (16
 * values, row-major) and `DIMENSIONS`. vtkSightlineTRXWriter writes all of these back.
 *
 * Memory: members are read in bounded blocks straight into the output arrays (stored members in
 * place, deflated ones inflated as a stream), never through a copy of the file.
 *
 * Pieces (pvbatch/pvserver ranks): piece p of n gets streamlines [p N / n, (p + 1) N / n) and
 * reads only their offsets, vertices, dpv and dps (groups are scanned for their members).
 *
 * Errors, named, for: a missing or malformed header, sizes that disagree with it (a member's
 * bytes, offsets past NB_VERTICES or decreasing), a member of unknown dtype or column count, a
 * non-integer offsets or groups dtype, group indices past NB_STREAMLINES, non-finite positions,
 * and zip archives that are not what they claim (see SightlineZip.h). Members TRX does not
 * define are skipped with a warning.
 */
#ifndef vtkSightlineTRXReader_h
#define vtkSightlineTRXReader_h

#include "SightlineIOModule.h" // for export macro
#include "vtkPolyDataAlgorithm.h"

#include <string> // for std::string

class SIGHTLINEIO_EXPORT vtkSightlineTRXReader : public vtkPolyDataAlgorithm
{
public:
  static vtkSightlineTRXReader* New();
  vtkTypeMacro(vtkSightlineTRXReader, vtkPolyDataAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /// A .trx (zip) file or a TRX directory.
  vtkSetStringMacro(FileName);
  vtkGetStringMacro(FileName);

  ///@{
  /**
   * With ReadFromInputString on, the reader parses InputString (the bytes of a whole .trx
   * archive) instead of FileName.
   */
  void SetInputString(const std::string& bytes);
  const std::string& GetInputString() const { return this->InputString; }
  vtkSetMacro(ReadFromInputString, bool);
  vtkGetMacro(ReadFromInputString, bool);
  vtkBooleanMacro(ReadFromInputString, bool);
  ///@}

  /**
   * Whether the path is a zip archive with a header.json member, or a directory with a
   * header.json file.
   */
  static int CanReadFile(const char* fileName);

protected:
  vtkSightlineTRXReader();
  ~vtkSightlineTRXReader() override;

  int RequestInformation(vtkInformation* request, vtkInformationVector** inputVector,
    vtkInformationVector* outputVector) override;
  int RequestData(vtkInformation* request, vtkInformationVector** inputVector,
    vtkInformationVector* outputVector) override;

  char* FileName = nullptr;
  std::string InputString;
  bool ReadFromInputString = false;

private:
  vtkSightlineTRXReader(const vtkSightlineTRXReader&) = delete;
  void operator=(const vtkSightlineTRXReader&) = delete;
};

#endif
