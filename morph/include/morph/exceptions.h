// SPDX-License-Identifier: Apache-2.0
#pragma once
/// \file exceptions.h
/// The errors MorphMill's libraries throw. Only apps/ catches them and turns them into exit codes.
#include <stdexcept>
#include <string>

namespace morph {

/// The user's input is wrong: a job key, a G-code line, a mesh file. The message names the file,
/// the JSON path or line, and the problem.
class InputError : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

/// A file could not be read or written.
class IoError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// A computation could not produce a valid result (for example a mesh that is not closed where a
/// closed one is required).
class GeometryError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// A resource limit set by the caller would be exceeded (memory cap, voxel count).
class LimitError : public std::length_error {
 public:
  using std::length_error::length_error;
};

/// The caller's interrupter asked the computation to stop.
class Interrupted : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace morph
