// SPDX-License-Identifier: BSD-3-Clause
/**
 * @class   vtkSightlineSWCReader
 * @brief   Reads SWC neuron morphologies (NeuroMorpho.Org, NEURON, Vaa3D) into vtkPolyData.
 *
 * An SWC file lists samples, one per line: `id type x y z radius parent`, with `parent` -1
 * (any negative value) for a root. Lines starting with `#` and blank lines are skipped, text
 * after a `#` is a comment, and fields after the seventh are ignored. Ids need not be sorted
 * or contiguous and a parent may come after its child; several roots (several trees, or
 * several soma samples) are fine.
 *
 * Output, one point per sample in file order:
 * - point data "Radius" (active scalars), "Type" (the SWC structure type: 1 soma, 2 axon, 3
 *   basal and 4 apical dendrite, ...), "SampleId" (the file's id) and "ParentIndex" (the point
 *   index of the parent, -1 for roots): the links that a tube mapper joins;
 * - polylines: every link once, in maximal unbranched chains from a root or a branch point to
 *   a branch point or a tip (what vtkTubeFilter takes); a root without children is a vertex.
 *
 * NeuroMorpho's three-point soma (a root and two samples one radius away along y, both linked
 * to it) is kept as given: joined by spheres and cones it is a cylinder of the soma radius
 * capped by spheres. Samples with radius 0 are kept and counted in a warning.
 *
 * Errors name the line: fewer than seven fields, a field that is no number (named, with its
 * text escaped to printable UTF-8), a number beyond double range, non-finite coordinates or
 * radius, a negative radius, a duplicate id, a parent id that is not in the file, or a cycle of
 * parents (reported with one id on it). Nothing is output then. Numbers too small for a
 * normal double (e.g. 1e-310) are read as they are.
 *
 * Pieces (pvbatch/pvserver ranks): the reader takes piece requests (CAN_HANDLE_PIECE_REQUEST);
 * piece 0 reads the whole file and every other piece is empty. SWC files are small (thousands
 * of samples, kilobytes to a few megabytes), so splitting a tree across ranks is not worth its
 * cost; piece 0 of 1 is the plain read.
 */
#ifndef vtkSightlineSWCReader_h
#define vtkSightlineSWCReader_h

#include "SightlineIOModule.h" // for export macro
#include "vtkPolyDataAlgorithm.h"

#include <string> // for std::string

class SIGHTLINEIO_EXPORT vtkSightlineSWCReader : public vtkPolyDataAlgorithm
{
public:
  static vtkSightlineSWCReader* New();
  vtkTypeMacro(vtkSightlineSWCReader, vtkPolyDataAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  vtkSetStringMacro(FileName);
  vtkGetStringMacro(FileName);

  ///@{
  /**
   * With ReadFromInputString on, the reader parses InputString (the text of a whole SWC
   * file) instead of FileName.
   */
  void SetInputString(const std::string& text);
  const std::string& GetInputString() const { return this->InputString; }
  vtkSetMacro(ReadFromInputString, bool);
  vtkGetMacro(ReadFromInputString, bool);
  vtkBooleanMacro(ReadFromInputString, bool);
  ///@}

  /**
   * Counts of the last read: roots, branch points (samples with two or more children) and
   * samples of radius 0.
   */
  vtkGetMacro(NumberOfRoots, vtkIdType);
  vtkGetMacro(NumberOfBranchPoints, vtkIdType);
  vtkGetMacro(NumberOfZeroRadii, vtkIdType);

protected:
  vtkSightlineSWCReader();
  ~vtkSightlineSWCReader() override;

  int RequestInformation(vtkInformation* request, vtkInformationVector** inputVector,
    vtkInformationVector* outputVector) override;
  int RequestData(vtkInformation* request, vtkInformationVector** inputVector,
    vtkInformationVector* outputVector) override;

  char* FileName = nullptr;
  std::string InputString;
  bool ReadFromInputString = false;
  vtkIdType NumberOfRoots = 0;
  vtkIdType NumberOfBranchPoints = 0;
  vtkIdType NumberOfZeroRadii = 0;

private:
  vtkSightlineSWCReader(const vtkSightlineSWCReader&) = delete;
  void operator=(const vtkSightlineSWCReader&) = delete;
};

#endif
