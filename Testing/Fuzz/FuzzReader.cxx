// SPDX-License-Identifier: BSD-3-Clause
// libFuzzer target for one Sightline::IO reader (SIGHTLINE_FUZZ_READER, set by CMake): the
// input is a whole file, parsed from memory through SetInputString/ReadFromInputString.
// Besides crashes, hangs, leaks and out-of-memory (libFuzzer, ASan, UBSan), it traps on
// results the readers promise never to give: an error or warning text that is not valid
// UTF-8, a polyline point index outside the points, a non-finite streamline point, image
// scalars that do not cover the image, or grid coordinates that are not finite and increasing. Each input is read whole and then as piece 1 of 3 (what
// a pvbatch/pvserver rank asks for), which must satisfy the same checks and hold no more points
// than the whole.
#include "vtkCallbackCommand.h"
#include "vtkCellArray.h"
#include "vtkCommand.h"
#include "vtkDataArray.h"
#include "vtkImageData.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPolyData.h"
#include "vtkRectilinearGrid.h"
#include SIGHTLINE_FUZZ_HEADER

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>

namespace
{
// Strict UTF-8 (RFC 3629), written independently of the readers' escaping.
bool ValidUtf8(const char* text)
{
  const auto* s = reinterpret_cast<const unsigned char*>(text);
  while (*s)
  {
    int extra = 0;
    std::uint32_t code = 0;
    if (*s < 0x80)
    {
      ++s;
      continue;
    }
    if ((*s & 0xE0) == 0xC0)
    {
      extra = 1;
      code = *s & 0x1F;
    }
    else if ((*s & 0xF0) == 0xE0)
    {
      extra = 2;
      code = *s & 0x0F;
    }
    else if ((*s & 0xF8) == 0xF0)
    {
      extra = 3;
      code = *s & 0x07;
    }
    else
    {
      return false;
    }
    for (int k = 1; k <= extra; ++k)
    {
      if ((s[k] & 0xC0) != 0x80)
      {
        return false;
      }
      code = (code << 6) | (s[k] & 0x3F);
    }
    const std::uint32_t smallest[4] = { 0, 0x80, 0x800, 0x10000 };
    if (code < smallest[extra] || code > 0x10FFFF || (code >= 0xD800 && code <= 0xDFFF))
    {
      return false;
    }
    s += extra + 1;
  }
  return true;
}

void CheckMessage(vtkObject*, unsigned long, void*, void* message)
{
  if (message && !ValidUtf8(static_cast<const char*>(message)))
  {
    __builtin_trap();
  }
}

void CheckOutput(vtkPolyData* output)
{
  const vtkIdType points = output->GetNumberOfPoints();
  for (vtkIdType i = 0; i < points; ++i)
  {
    double p[3];
    output->GetPoint(i, p);
    if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2]))
    {
      __builtin_trap();
    }
  }
  vtkCellArray* lines = output->GetLines();
  const vtkIdType* ids = nullptr;
  vtkIdType count = 0;
  for (lines->InitTraversal(); lines->GetNextCell(count, ids);)
  {
    for (vtkIdType k = 0; k < count; ++k)
    {
      if (ids[k] < 0 || ids[k] >= points)
      {
        __builtin_trap();
      }
    }
  }
}

void CheckOutput(vtkImageData* output)
{
  vtkDataArray* scalars = output->GetPointData()->GetScalars();
  if (scalars && scalars->GetNumberOfTuples() != output->GetNumberOfPoints())
  {
    __builtin_trap();
  }
}
void CheckOutput(vtkRectilinearGrid* output)
{
  // Coordinates finite and strictly increasing (the spherical mapper's convention), every
  // point array covering the grid.
  vtkDataArray* axes[3] = { output->GetXCoordinates(), output->GetYCoordinates(),
    output->GetZCoordinates() };
  vtkIdType points = 1;
  for (vtkDataArray* axis : axes)
  {
    if (!axis)
    {
      return;
    }
    for (vtkIdType i = 0; i < axis->GetNumberOfTuples(); ++i)
    {
      const double v = axis->GetComponent(i, 0);
      if (!std::isfinite(v) || (i > 0 && !(v > axis->GetComponent(i - 1, 0))))
      {
        __builtin_trap();
      }
    }
    points *= axis->GetNumberOfTuples();
  }
  if (output->GetNumberOfPoints() > 0 && points != output->GetNumberOfPoints())
  {
    __builtin_trap();
  }
  vtkPointData* data = output->GetPointData();
  for (int a = 0; a < data->GetNumberOfArrays(); ++a)
  {
    if (data->GetArray(a)->GetNumberOfTuples() != output->GetNumberOfPoints())
    {
      __builtin_trap();
    }
  }
}
} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
  vtkNew<vtkCallbackCommand> check;
  check->SetCallback(CheckMessage);
  vtkNew<SIGHTLINE_FUZZ_READER> reader;
  reader->AddObserver(vtkCommand::ErrorEvent, check);
  reader->AddObserver(vtkCommand::WarningEvent, check);
  reader->SetInputString(std::string(reinterpret_cast<const char*>(data), size));
  reader->ReadFromInputStringOn();
  reader->Update();
  CheckOutput(reader->GetOutput());
  const vtkIdType whole = reader->GetOutput()->GetNumberOfPoints();
  reader->Modified(); // a piece inside the whole output would not be read again
  reader->UpdatePiece(1, 3, 0);
  CheckOutput(reader->GetOutput());
  if (whole > 0 && reader->GetOutput()->GetNumberOfPoints() > whole)
  {
    __builtin_trap();
  }
  return 0;
}
