// SPDX-License-Identifier: BSD-3-Clause
/**
 * @class   vtkSightlineTRXWriter
 * @brief   Writes polylines (a tractogram) as a TRX file, zip archive or directory.
 *
 * Each line cell of the input becomes a streamline, its points in cell order (shared points are
 * written once per streamline that uses them); vertices, polygons and strips are left out with a
 * warning. What vtkSightlineTRXReader makes is written back:
 * - point data arrays: `dpv/NAME[.COLUMNS].DTYPE`, cell data of the lines: `dps/...`;
 * - cell arrays named `group:NAME` (non-zero: a member): `groups/NAME.uint32` (uint64 past 2^32
 *   streamlines), and field data `dpg:GROUP:NAME`: `dpg/GROUP/NAME...`;
 * - field data `VOXEL_TO_RASMM` (16 values) and `DIMENSIONS` (3) into header.json (the
 *   identity and 1 1 1 otherwise, as trx-python writes them).
 * Arrays keep their type (TRX has no string arrays: those are skipped with a warning); names
 * lose the characters TRX member names cannot hold ('.', '/'), with a warning.
 *
 * Offsets are uint64, one per streamline and one more (NB_VERTICES), as current trx-python
 * writes them. The archive is stored (trx-python memory-maps stored members) unless Compress is
 * on (deflate); members are streamed, zip64 where sizes need it.
 */
#ifndef vtkSightlineTRXWriter_h
#define vtkSightlineTRXWriter_h

#include "SightlineIOModule.h" // for export macro
#include "vtkWriter.h"

class vtkPolyData;

class SIGHTLINEIO_EXPORT vtkSightlineTRXWriter : public vtkWriter
{
public:
  static vtkSightlineTRXWriter* New();
  vtkTypeMacro(vtkSightlineTRXWriter, vtkWriter);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  vtkSetStringMacro(FileName);
  vtkGetStringMacro(FileName);

  enum PositionTypes
  {
    POSITIONS_AS_INPUT = 0, ///< float32 for float points, float64 for double points
    POSITIONS_FLOAT16,
    POSITIONS_FLOAT32,
    POSITIONS_FLOAT64,
  };
  ///@{
  /**
   * The dtype of positions. float16 halves the file (11 significant bits: 0.03 mm at 100 mm
   * from the origin) and fails for coordinates beyond 65504.
   */
  vtkSetClampMacro(PositionsType, int, POSITIONS_AS_INPUT, POSITIONS_FLOAT64);
  vtkGetMacro(PositionsType, int);
  ///@}

  ///@{
  /** Deflate the archive's members (off: stored, what trx-python maps in place). */
  vtkSetMacro(Compress, bool);
  vtkGetMacro(Compress, bool);
  vtkBooleanMacro(Compress, bool);
  ///@}

  ///@{
  /**
   * Write TRX's directory form (FileName is a directory, created; an existing one must be
   * empty) instead of a zip archive.
   */
  vtkSetMacro(WriteToDirectory, bool);
  vtkGetMacro(WriteToDirectory, bool);
  vtkBooleanMacro(WriteToDirectory, bool);
  ///@}

  vtkPolyData* GetInput();

protected:
  vtkSightlineTRXWriter();
  ~vtkSightlineTRXWriter() override;

  void WriteData() override;
  int FillInputPortInformation(int port, vtkInformation* info) override;

  char* FileName = nullptr;
  int PositionsType = POSITIONS_AS_INPUT;
  bool Compress = false;
  bool WriteToDirectory = false;

private:
  vtkSightlineTRXWriter(const vtkSightlineTRXWriter&) = delete;
  void operator=(const vtkSightlineTRXWriter&) = delete;
};

#endif
