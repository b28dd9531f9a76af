// SPDX-License-Identifier: BSD-3-Clause
// vtkSightlineSphericalFieldSource asked for pieces (as pvbatch/pvserver ranks do) and for
// sub-extents: each is exactly the corresponding part of the whole grid (coordinates and
// values), whatever the split, with the whole grid's breakpoints (aligned with PREM's layers
// or the step), and the pieces split the cells. No window is opened.
#include "vtkSightlineSphericalFieldSource.h"

#include "vtkCellData.h"
#include "vtkDataArray.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkRectilinearGrid.h"
#include "vtkSmartPointer.h"
#include "vtkStructuredData.h"

#include <gtest/gtest.h>

#include <string>

namespace
{
vtkSmartPointer<vtkRectilinearGrid> Copy(vtkSightlineSphericalFieldSource* source)
{
  auto copy = vtkSmartPointer<vtkRectilinearGrid>::New();
  copy->DeepCopy(source->GetOutput());
  return copy;
}

void ExpectPartOfTheWhole(vtkRectilinearGrid* whole, vtkRectilinearGrid* part, bool cells,
  const std::string& what)
{
  int extent[6], wholeExtent[6];
  part->GetExtent(extent);
  whole->GetExtent(wholeExtent);
  vtkDataArray* coordinates[2][3] = { { whole->GetXCoordinates(), whole->GetYCoordinates(),
                                        whole->GetZCoordinates() },
    { part->GetXCoordinates(), part->GetYCoordinates(), part->GetZCoordinates() } };
  for (int a = 0; a < 3; ++a)
  {
    ASSERT_EQ(coordinates[1][a]->GetNumberOfTuples(), extent[2 * a + 1] - extent[2 * a] + 1) << what;
    for (int i = extent[2 * a]; i <= extent[2 * a + 1]; ++i)
      ASSERT_EQ(coordinates[1][a]->GetComponent(i - extent[2 * a], 0),
        coordinates[0][a]->GetComponent(i - wholeExtent[2 * a], 0))
        << what << " axis " << a << " index " << i;
  }
  vtkDataArray* all = cells ? whole->GetCellData()->GetScalars() : whole->GetPointData()->GetScalars();
  vtkDataArray* some = cells ? part->GetCellData()->GetScalars() : part->GetPointData()->GetScalars();
  ASSERT_TRUE(all && some) << what;
  const int last = cells ? 0 : 1; // cells end one before the last point
  ASSERT_EQ(some->GetNumberOfTuples(), cells ? part->GetNumberOfCells() : part->GetNumberOfPoints()) << what;
  for (int k = extent[4]; k < extent[5] + last; ++k)
    for (int j = extent[2]; j < extent[3] + last; ++j)
      for (int i = extent[0]; i < extent[1] + last; ++i)
      {
        int ijk[3] = { i, j, k };
        // (vtkRectilinearGrid's ComputeCellId ignores the extent's start.)
        const vtkIdType a = cells ? vtkStructuredData::ComputeCellIdForExtent(wholeExtent, ijk)
                                  : vtkStructuredData::ComputePointIdForExtent(wholeExtent, ijk);
        const vtkIdType b = cells ? vtkStructuredData::ComputeCellIdForExtent(extent, ijk)
                                  : vtkStructuredData::ComputePointIdForExtent(extent, ijk);
        ASSERT_EQ(some->GetComponent(b, 0), all->GetComponent(a, 0))
          << what << " at " << i << "," << j << "," << k;
      }
}
} // namespace

TEST(SphericalFieldSource, PiecesAndSubExtentsArePartsOfTheWholeGrid)
{
  for (const int field : { vtkSightlineSphericalFieldSource::STEP,
         vtkSightlineSphericalFieldSource::PREM_DENSITY })
    for (const bool cells : { true, false })
    {
      const std::string what = std::string(field == vtkSightlineSphericalFieldSource::STEP ? "step" : "PREM") +
        (cells ? ", cell data" : ", point data");
      vtkNew<vtkSightlineSphericalFieldSource> source;
      source->SetField(field);
      source->SetRadialResolution(13);
      source->SetPolarResolution(6);
      source->SetAzimuthalResolution(9);
      source->SetPerturbationAmplitude(0.1);
      source->SetOutputCellData(cells);
      source->UpdatePiece(0, 1, 0);
      const vtkSmartPointer<vtkRectilinearGrid> whole = Copy(source);
      ASSERT_GT(whole->GetNumberOfCells(), 0) << what;
      for (const int pieces : { 1, 2, 3, 4, 7 })
      {
        vtkIdType cellCount = 0;
        for (int p = 0; p < pieces; ++p)
        {
          source->Modified(); // a piece inside the last output would not be made again
          source->UpdatePiece(p, pieces, 0);
          const vtkSmartPointer<vtkRectilinearGrid> piece = Copy(source);
          if (piece->GetNumberOfPoints() == 0)
            continue;
          const std::string at = what + ", piece " + std::to_string(p) + " of " + std::to_string(pieces);
          ExpectPartOfTheWhole(whole, piece, cells, at);
          if (pieces > 1)
          {
            EXPECT_LT(piece->GetNumberOfCells(), whole->GetNumberOfCells()) << at;
          }
          cellCount += piece->GetNumberOfCells();
        }
        EXPECT_EQ(cellCount, whole->GetNumberOfCells()) << what << ", " << pieces << " pieces";
      }
      int w[6];
      whole->GetExtent(w);
      const int sub[][6] = { { 0, 1, 0, 1, 0, 1 }, { w[1] - 3, w[1], 2, 4, w[5] - 1, w[5] },
        { 1, w[1] / 2, 0, w[3], 3, 7 } };
      for (const auto& extent : sub)
      {
        source->Modified();
        source->UpdateExtent(extent);
        const vtkSmartPointer<vtkRectilinearGrid> part = Copy(source);
        int got[6];
        part->GetExtent(got);
        for (int a = 0; a < 6; ++a)
          EXPECT_EQ(got[a], extent[a]) << what;
        ExpectPartOfTheWhole(whole, part, cells, what + " sub-extent");
      }
    }
}
