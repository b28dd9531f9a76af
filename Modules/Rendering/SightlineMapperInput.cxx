// SPDX-License-Identifier: BSD-3-Clause
#include "SightlineMapperInput.h"

#include "vtkAlgorithm.h"
#include "vtkAppendFilter.h"
#include "vtkAppendPolyData.h"
#include "vtkCompositeDataIterator.h"
#include "vtkCompositeDataSet.h"
#include "vtkDataArray.h"
#include "vtkDataSet.h"
#include "vtkNew.h"
#include "vtkPointSet.h"
#include "vtkPolyData.h"
#include "vtkUnstructuredGrid.h"

#include <algorithm>
#include <cmath>

namespace
{
// Calls `visit` with every non-empty node of a composite dataset.
template <typename Visit>
void ForEachLeaf(vtkCompositeDataSet* composite, Visit&& visit)
{
  vtkSmartPointer<vtkCompositeDataIterator> it;
  it.TakeReference(composite->NewIterator());
  it->SkipEmptyNodesOn();
  for (it->InitTraversal(); !it->IsDoneWithTraversal(); it->GoToNextItem())
  {
    if (vtkDataObject* leaf = it->GetCurrentDataObject())
    {
      visit(leaf);
    }
  }
}
} // namespace

//------------------------------------------------------------------------------
SightlineMapperInput::SightlineMapperInput(const char* leafType, Leaves leaves)
  : LeafType(leafType)
  , Mode(leaves)
{
}

//------------------------------------------------------------------------------
vtkMTimeType SightlineMapperInput::GetInputTime(vtkAlgorithm* mapper) const
{
  vtkDataObject* input =
    mapper->GetNumberOfInputConnections(0) > 0 ? mapper->GetInputDataObject(0, 0) : nullptr;
  if (!input)
  {
    return 0;
  }
  vtkMTimeType time = input->GetMTime();
  if (auto* composite = vtkCompositeDataSet::SafeDownCast(input))
  {
    ForEachLeaf(composite, [&time](vtkDataObject* leaf) { time = std::max(time, leaf->GetMTime()); });
  }
  return time;
}

//------------------------------------------------------------------------------
vtkDataSet* SightlineMapperInput::Get(vtkAlgorithm* mapper, bool update)
{
  if (mapper->GetNumberOfInputConnections(0) < 1)
  {
    this->Source = nullptr;
    this->Flat = nullptr;
    return nullptr;
  }
  if (update)
  {
    mapper->GetInputAlgorithm()->Update();
  }
  vtkDataObject* input = mapper->GetInputDataObject(0, 0);
  if (!input)
  {
    this->Source = nullptr;
    this->Flat = nullptr;
    return nullptr;
  }
  if (input == this->Source && this->GetInputTime(mapper) <= this->FlattenTime.GetMTime())
  {
    return this->Flat;
  }
  this->Source = input;
  this->FlattenTime.Modified();
  this->Flat = nullptr;
  this->Offsets.assign(1, 0);
  this->Composite = false;

  auto* composite = vtkCompositeDataSet::SafeDownCast(input);
  if (!composite)
  {
    auto* dataset = vtkDataSet::SafeDownCast(input);
    if (!dataset || !dataset->IsA(this->LeafType.c_str()))
    {
      vtkErrorWithObjectMacro(mapper, << "The input is a " << input->GetClassName() << "; "
                                      << mapper->GetClassName() << " draws a " << this->LeafType
                                      << " or a composite dataset of them.");
      return nullptr;
    }
    if (dataset->GetNumberOfPoints() > 0)
    {
      this->Flat = dataset;
    }
    return this->Flat;
  }

  this->Composite = true;
  std::vector<vtkDataSet*> leaves;
  std::vector<const char*> wrongTypes;
  ForEachLeaf(composite,
    [&](vtkDataObject* leaf)
    {
      auto* dataset = vtkDataSet::SafeDownCast(leaf);
      if (!dataset || !dataset->IsA(this->LeafType.c_str()))
      {
        wrongTypes.push_back(leaf->GetClassName());
      }
      else if (dataset->GetNumberOfPoints() > 0)
      {
        leaves.push_back(dataset);
      }
    });
  if (!wrongTypes.empty())
  {
    vtkErrorWithObjectMacro(mapper, << wrongTypes.size() << " leaf dataset(s) of the "
                                    << input->GetClassName() << " input are not a "
                                    << this->LeafType << " (the first is a " << wrongTypes[0]
                                    << "); " << mapper->GetClassName()
                                    << " leaves them out.");
  }
  if (leaves.empty())
  {
    return nullptr;
  }
  if (leaves.size() == 1)
  {
    this->Flat = leaves[0];
    return this->Flat;
  }
  if (this->Mode == Leaves::First)
  {
    vtkWarningWithObjectMacro(mapper, << "The " << input->GetClassName() << " input has "
                                      << leaves.size() << " non-empty " << this->LeafType
                                      << " leaves; " << mapper->GetClassName()
                                      << " draws one dataset, the first leaf.");
    this->Flat = leaves[0];
    return this->Flat;
  }

  // The union, in leaf order: leaf k's points start at Offsets[k].
  this->Offsets.clear();
  vtkIdType offset = 0;
  for (vtkDataSet* leaf : leaves)
  {
    this->Offsets.push_back(offset);
    offset += leaf->GetNumberOfPoints();
  }
  const bool polyData = std::all_of(
    leaves.begin(), leaves.end(), [](vtkDataSet* leaf) { return leaf->IsA("vtkPolyData"); });
  if (polyData)
  {
    vtkNew<vtkAppendPolyData> append;
    for (vtkDataSet* leaf : leaves)
    {
      append->AddInputData(static_cast<vtkPolyData*>(leaf));
    }
    append->Update();
    this->Flat = append->GetOutput();
  }
  else
  {
    vtkNew<vtkAppendFilter> append;
    append->MergePointsOff();
    for (vtkDataSet* leaf : leaves)
    {
      append->AddInputData(leaf);
    }
    append->Update();
    this->Flat = append->GetOutput();
  }
  return this->Flat;
}

//------------------------------------------------------------------------------
std::vector<vtkPointSet*> SightlineMapperInput::PointSets(vtkDataObject* data)
{
  std::vector<vtkPointSet*> sets;
  if (auto* pointSet = vtkPointSet::SafeDownCast(data))
  {
    sets.push_back(pointSet);
  }
  else if (auto* composite = vtkCompositeDataSet::SafeDownCast(data))
  {
    vtkSmartPointer<vtkCompositeDataIterator> it;
    it.TakeReference(composite->NewIterator());
    for (it->InitTraversal(); !it->IsDoneWithTraversal(); it->GoToNextItem())
    {
      if (auto* leaf = vtkPointSet::SafeDownCast(it->GetCurrentDataObject()))
      {
        sets.push_back(leaf);
      }
    }
  }
  return sets;
}

//------------------------------------------------------------------------------
double SightlineMapperInput::LargestRadius(vtkDataArray* array, double radius, double scale)
{
  double largest = std::isfinite(radius) ? std::abs(radius) : 0.0;
  if (!array || array->GetNumberOfComponents() != 1)
  {
    return largest;
  }
  double range[2];
  array->GetFiniteRange(range, 0);
  if (range[0] <= range[1])
  {
    largest = std::max({ largest, std::abs(range[0] * scale), std::abs(range[1] * scale) });
  }
  return largest;
}
