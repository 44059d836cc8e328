#pragma once
/// @file Error type thrown for every refusal of bad input (files, meshes, positions, options).
#include <stdexcept>
#include <string>

namespace mccd {

/// Thrown when input is refused. The message names what was wrong and where
/// ("cloth.ply: face 1022: vertex index 46611 out of range [0, 46598)").
/// Whatever raised it has not changed any state.
class Error : public std::runtime_error {
 public:
  explicit Error(const std::string& what) : std::runtime_error(what) {}
};

}  // namespace mccd
