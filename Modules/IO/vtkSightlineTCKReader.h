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
 * A file cut short (no Inf triplet) keeps its complete streamlines, with a warning; a `count`
 * that disagrees with the streamlines read is reported as a warning too. A missing file, a
 * wrong first line, a header without END, `file` or a known `datatype`, or a data offset
 * beyond the file are errors.
 */
#ifndef vtkSightlineTCKReader_h
#define vtkSightlineTCKReader_h

#include "SightlineIOModule.h" // for export macro
#include "vtkPolyDataAlgorithm.h"

class SIGHTLINEIO_EXPORT vtkSightlineTCKReader : public vtkPolyDataAlgorithm
{
public:
  static vtkSightlineTCKReader* New();
  vtkTypeMacro(vtkSightlineTCKReader, vtkPolyDataAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  vtkSetStringMacro(FileName);
  vtkGetStringMacro(FileName);

  /**
   * Whether the file starts like a .tck file.
   */
  static int CanReadFile(const char* fileName);

protected:
  vtkSightlineTCKReader();
  ~vtkSightlineTCKReader() override;

  int RequestData(vtkInformation* request, vtkInformationVector** inputVector,
    vtkInformationVector* outputVector) override;

  char* FileName = nullptr;

private:
  vtkSightlineTCKReader(const vtkSightlineTCKReader&) = delete;
  void operator=(const vtkSightlineTCKReader&) = delete;
};

#endif
