// SPDX-License-Identifier: BSD-3-Clause
#include "SightlineTracer.h"

#include "vtkAbstractMapper.h"

SightlineTracer::~SightlineTracer() = default;

SightlineTracer* SightlineTracer::Of(vtkAbstractMapper* mapper)
{
  return dynamic_cast<SightlineTracer*>(mapper);
}
