// SPDX-License-Identifier: BSD-3-Clause
/**
 * @class   vtkSightlineMIFReader
 * @brief   Reads MRtrix3 images (.mif, .mif.gz) into vtkImageData, e.g. SH coefficient volumes.
 *
 * The output has the image's first three axes as VTK's x, y, z (x fastest, whatever the order
 * and direction of the axes on disk: the header's `layout`), spacing from `vox`, origin 0, and
 * one float point array named "SHCoefficients" (also the active scalars) whose components are
 * the 4th axis (one component for a 3-D image). GetTransformMatrix() maps VTK data coordinates
 * (index * spacing) to scanner coordinates: it is MRtrix's `transform` (rotation and
 * translation, spacing factored out).
 *
 * Like vtkNIFTIImageReader, the reader keeps that matrix a proper rotation: when the header's
 * rotation has a negative determinant (a left-handed voxel grid, qfac = -1 in NIfTI terms), the
 * slice order (z) is reversed and the matrix's third column negated and its translation moved to
 * the last slice; GetSlicesReversed() tells. A .mif written by `mrconvert -config
 * RealignTransform false` from a NIfTI therefore reads into exactly the image and matrix that
 * vtkNIFTIImageReader (TimeAsVectorOn(), GetQFormMatrix()) gives for that NIfTI. Voxel values
 * are never changed; any direction frame in them (e.g. SH coefficients in scanner axes, as
 * MRtrix writes them) is the file's.
 *
 * Supported: single-file images (`file: . OFFSET`), gzip-compressed or not; 2 to 4 axes (more
 * only of size 1); datatypes Int8, UInt8, Int16, UInt16, Int32, UInt32, Float32 and Float64,
 * little- or big-endian (LE/BE suffix; none means this machine's order), with the optional
 * `scaling: offset,multiplier` applied. Values are converted to float.
 *
 * Errors (vtkErrorMacro, an empty output, no crash): a missing or unreadable file, a first line
 * other than "mrtrix image", a missing or malformed dim/vox/layout/datatype/file entry, an
 * unsupported datatype (Bit, complex, 64-bit integers), a separate data file, more than 4 axes,
 * a data offset inside the header, an image whose size overflows 64 bits, and data shorter
 * than the header promises. Sizes are checked against the file's length before anything is
 * allocated (for gzip, against the most a stream of that length can inflate to, and the data
 * are then read in steps), so a small file cannot make the reader allocate much. Text quoted
 * from the file in messages is escaped to printable UTF-8.
 *
 * Pieces (pvbatch/pvserver ranks): the reader produces any sub-extent of WHOLE_EXTENT
 * (CAN_PRODUCE_SUB_EXTENT), so the pipeline turns a piece request into an UPDATE_EXTENT with
 * its extent translator, and only that extent is read, with all components (the 4th axis).
 * The file is never loaded whole: the reader reads the contiguous run of data between the first
 * and the last requested position along the slowest axis on disk (for MRtrix's usual layouts, z)
 * a step at a time, skipping what comes before it by seeking (by inflating and dropping for
 * .mif.gz), and keeps only the requested voxels. As for any structured data set, neighbouring
 * pieces share the voxels on their common face and split the cells. Truncation is reported
 * when the requested data are not all there.
 *
 * @sa vtkNIFTIImageReader
 */
#ifndef vtkSightlineMIFReader_h
#define vtkSightlineMIFReader_h

#include "SightlineIOModule.h" // for export macro
#include "vtkImageAlgorithm.h"
#include "vtkNew.h" // for vtkNew

#include <string> // for std::string

class vtkMatrix4x4;

class SIGHTLINEIO_EXPORT vtkSightlineMIFReader : public vtkImageAlgorithm
{
public:
  static vtkSightlineMIFReader* New();
  vtkTypeMacro(vtkSightlineMIFReader, vtkImageAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /**
   * The .mif or .mif.gz file to read (gzip is recognised by its content, not its name).
   */
  vtkSetStringMacro(FileName);
  vtkGetStringMacro(FileName);
  ///@}

  ///@{
  /**
   * With ReadFromInputString on, the reader parses InputString (the bytes of a whole .mif or
   * .mif.gz file) instead of FileName, e.g. for data that never touches the disk.
   */
  void SetInputString(const std::string& bytes);
  const std::string& GetInputString() const { return this->InputString; }
  vtkSetMacro(ReadFromInputString, bool);
  vtkGetMacro(ReadFromInputString, bool);
  vtkBooleanMacro(ReadFromInputString, bool);
  ///@}

  /**
   * 1 if the file starts with MRtrix's magic line "mrtrix image" (compressed or not), else 0.
   */
  static int CanReadFile(const char* fileName);

  /**
   * The matrix from VTK data coordinates (index * spacing, origin 0) to scanner coordinates,
   * valid after UpdateInformation(). Identity before a header has been read.
   */
  vtkMatrix4x4* GetTransformMatrix();

  /**
   * True when the last header read had a left-handed transform, so the slices were reversed
   * (see the class description).
   */
  vtkGetMacro(SlicesReversed, bool);

  /**
   * The header's datatype string (e.g. "Float32LE") of the last file read, or empty.
   */
  const char* GetDataTypeName() { return this->DataTypeName.c_str(); }

protected:
  vtkSightlineMIFReader();
  ~vtkSightlineMIFReader() override;

  int RequestInformation(vtkInformation* request, vtkInformationVector** inputVector,
    vtkInformationVector* outputVector) override;
  int RequestData(vtkInformation* request, vtkInformationVector** inputVector,
    vtkInformationVector* outputVector) override;

  char* FileName = nullptr;
  std::string InputString;
  bool ReadFromInputString = false;
  vtkNew<vtkMatrix4x4> TransformMatrix;
  bool SlicesReversed = false;
  std::string DataTypeName;

private:
  vtkSightlineMIFReader(const vtkSightlineMIFReader&) = delete;
  void operator=(const vtkSightlineMIFReader&) = delete;
};

#endif
