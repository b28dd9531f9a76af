# SPDX-License-Identifier: BSD-3-Clause
# Debian's OpenImageIO target lists /usr/include/opencv4 among its include directories even when
# OpenCV's headers are not installed (OpenImageIO only needs them for its own OpenCV plugin).
# Keep the directories that exist so CMake does not reject the target.
find_package(OpenImageIO REQUIRED)
foreach(target IN ITEMS OpenImageIO::OpenImageIO OpenImageIO::OpenImageIO_Util)
  if(TARGET ${target})
    get_target_property(dirs ${target} INTERFACE_INCLUDE_DIRECTORIES)
    if(dirs)
      set(existing)
      foreach(dir IN LISTS dirs)
        if(EXISTS "${dir}" OR dir MATCHES "^\\$<")
          list(APPEND existing "${dir}")
        endif()
      endforeach()
      set_target_properties(${target} PROPERTIES INTERFACE_INCLUDE_DIRECTORIES "${existing}")
    endif()
  endif()
endforeach()
