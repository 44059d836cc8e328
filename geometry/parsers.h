#pragma once
/// @file Internal: the file readers' in-memory entry points. Each parses the bytes of one
/// whole file, `name` standing for the file in error messages, exactly as the public reader
/// of that format does after reading the file (the fuzz targets and the tests call these).
#include <string>
#include <string_view>
#include <vector>

#include <mccd/geometry/mesh.h>
#include <mccd/geometry/query_io.h>

namespace mccd::detail {

/// Wavefront OBJ text (see read_obj).
TriMesh parse_obj(const std::string& name, std::string_view text);
/// A PLY file, header and data, any of the three formats (see read_ply).
TriMesh parse_ply(const std::string& name, std::string_view bytes);
/// Rational CCD query CSV text (see read_query_csv).
std::vector<CcdQuery> parse_query_csv(const std::string& name, std::string_view text);

}  // namespace mccd::detail
