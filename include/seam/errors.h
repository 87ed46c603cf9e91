// seam: the exceptions the library throws. Library code never aborts or exits.
//
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <stdexcept>
#include <string>

namespace seam {

/// Base of every exception seam throws.
class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// The input is wrong: a file that is not a valid triangle mesh or polyline file, a curve far
/// from the surface, an option out of range. The message is one line a user understands,
/// starting with the file name where there is one ("tow.off: face 17 has ..."). CLI exit code 2.
class InvalidInput : public Error {
 public:
  using Error::Error;
};

/// A file could not be read or written (missing, a directory, permission denied). Exit code 2.
class IOError : public Error {
 public:
  using Error::Error;
};

/// The algorithm could not produce a valid result from valid input: for example the float
/// kernel's rounded arithmetic produced an inconsistent triangulation. CLI exit code 3.
class InternalError : public Error {
 public:
  using Error::Error;
};

}  // namespace seam
