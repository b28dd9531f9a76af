// SPDX-License-Identifier: BSD-3-Clause
/**
 * @file SightlineOpenGL.h
 * @brief OpenGL through whatever loader the VTK in use provides.
 *
 * VTK up to 9.3 (Debian 12 and 13, ParaView 5.11 and 5.13) loads OpenGL with glew
 * (vtk_glew.h); VTK 9.4 replaced it with glad (vtk_glad.h), which PyPI's VTK wheels use.
 * Both declare the same gl* entry points, so this is the only place that knows which one.
 */
#ifndef SightlineOpenGL_h
#define SightlineOpenGL_h

#if __has_include("vtk_glad.h")
#include "vtk_glad.h" // IWYU pragma: export
#else
#include "vtk_glew.h" // IWYU pragma: export
#endif

#endif
