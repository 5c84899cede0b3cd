// SPDX-License-Identifier: MIT
#pragma once
/// @file static_formats.h
/// Static mesh files as unrigged models (see `make_static_model`): Wavefront OBJ, PLY and STL
/// through VTK's readers (vtkOBJReader, vtkPLYReader, vtkSTLReader), and OFF (Object File
/// Format) parsed here, since VTK 9.1 has no OFF reader. Polygons are triangulated; OBJ texture
/// coordinates and normals, PLY normals, texture coordinates and colours, and OFF normals, colours
/// and texture coordinates are carried as corner attributes.

#include <string>

#include "deepcut/core/io/static_mesh.h"
#include "deepcut/plugins/formats.h"

namespace deepcut::plugins {

/// Reads an .obj, .ply, .stl or .off file (by extension, case-insensitive).
/// Every file is checked before a reader sees it: it must exist, be a regular file, not be empty
/// or larger than 2 GiB; a PLY header and a binary STL triangle count must fit the file's size
/// (so a tiny file cannot claim ten million triangles); VTK's own messages are captured, never
/// printed, and become the error's text.
/// @throws Error{Io} when the file cannot be read, Error{InvalidInput} `"PATH: problem"` when it
///         is malformed (truncated, NaN, an index out of range, no faces, ...).
Model read_static_model(const std::string& path);

/// Parses OFF text (`OFF`, `COFF`, `NOFF`, `STOFF` and their combinations; `#` comments).
/// Polygons are split into triangle fans. Counts in the header are checked against the text's
/// size before anything is reserved; every index and number is checked.
/// @param file  names the input in messages.
/// @throws Error{InvalidInput} `"FILE: problem"` for anything malformed.
StaticMesh parse_off(const std::string& text, const std::string& file);

/// Registers the four formats ("Wavefront OBJ", "PLY", "STL", "OFF").
void register_static_formats(FormatRegistry& registry);

}  // namespace deepcut::plugins
