// SPDX-License-Identifier: BSD-3-Clause
// The one way a Sightline mapper turns its input data object into the single dataset it draws:
// a dataset as it is, a composite dataset (vtkMultiBlockDataSet, vtkPartitionedDataSet,
// vtkPartitionedDataSetCollection: what ParaView hands a mapper) flattened to its leaves, and
// an empty input (no connection, no points, no non-empty leaf) as nothing, quietly.
// Private to the Rendering module (not wrapped, not installed).
#pragma once

#include "vtkSmartPointer.h" // for vtkSmartPointer
#include "vtkTimeStamp.h"    // for vtkTimeStamp
#include "vtkType.h"         // for vtkIdType, vtkMTimeType

#include <string>
#include <vector>

class vtkAlgorithm;
class vtkDataObject;
class vtkDataSet;

class SightlineMapperInput
{
public:
  /// How a mapper draws a composite input.
  enum class Leaves
  {
    /// The union of every non-empty leaf, appended into one dataset (point sets: spheres,
    /// tubes). All vtkPolyData leaves give a vtkPolyData (cells kept, their point ids
    /// offset), other mixes a vtkUnstructuredGrid; point data arrays every leaf has are kept.
    Append,
    /// One leaf (images and grids: glyphs, volumes). Several non-empty leaves: the first is
    /// drawn, with a warning naming their count.
    First
  };

  /// `leafType` is the VTK class every drawn dataset must be (e.g. "vtkPointSet"); leaves of
  /// another type are left out with an error naming their type.
  SightlineMapperInput(const char* leafType, Leaves leaves);

  /// Updates the mapper's input (unless `update` is false, e.g. for a static mapper) and
  /// returns the dataset to draw, or nullptr when there is nothing to draw: no input
  /// connection, a null input, no points, a composite without non-empty leaves of the right
  /// type. Only a wrong type is reported; emptiness is quiet. Flattening is done again only
  /// when the input (or one of its leaves) changed, so its messages are not repeated.
  vtkDataSet* Get(vtkAlgorithm* mapper, bool update = true);

  /// Modification time of the input, its leaves included (0 without an input).
  vtkMTimeType GetInputTime(vtkAlgorithm* mapper) const;

  /// With Leaves::Append: the index of the first point of each appended leaf in the dataset
  /// Get() returns (a single entry 0 for a dataset that was not a composite), so that point
  /// ids stored in a leaf's arrays can be made ids of the union.
  const std::vector<vtkIdType>& GetLeafPointOffsets() const { return this->Offsets; }

  /// The point sets of `data`: itself, or every leaf of a composite (no flattening, no messages).
  static std::vector<class vtkPointSet*> PointSets(vtkDataObject* data);

  /// The largest of `radius` and of the (finite) values of `array` (one component, NaN
  /// skipped) times `scale`, or `radius` when the array is null or has several components:
  /// how far the spheres and tubes of one point set reach beyond their points.
  static double LargestRadius(class vtkDataArray* array, double radius, double scale);

  /// Whether the last input was a composite dataset.
  bool WasComposite() const { return this->Composite; }

private:
  std::string LeafType;
  Leaves Mode;
  vtkDataObject* Source = nullptr; // not owned: only compared with the current input
  vtkTimeStamp FlattenTime;
  vtkSmartPointer<vtkDataSet> Flat;
  std::vector<vtkIdType> Offsets;
  bool Composite = false;
};
