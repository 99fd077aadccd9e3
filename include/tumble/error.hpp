// The errors tumble throws. Every bad input (a malformed scene, a degenerate shape, a NaN, a bad
// API call) ends in one of these, with a message that names what was wrong and the value it had.
#pragma once

#include <stdexcept>
#include <string>

namespace tumble {

// Any error of tumble's API; what() is the whole message.
struct Error : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// A scene that cannot be loaded or fails its check. what() is the full one-line message:
//   FILE:LINE:COLUMN: field 'bodies[2].shape.radius': expected a positive number ..., got -1
// For a scene built in code there is no line: `SOURCE: field 'bodies[2].mass': ...`; where there
// is no field either (a file that cannot be opened) it reads `FILE: reason`.
struct SceneError : Error {
  SceneError(std::string file, int line, int column, std::string field, std::string reason);

  std::string file;    // the source name given to the loader (a path for files)
  int line = 0;        // 1-based; 0 when the error has no position in the text
  int column = 0;      // 1-based; 0 when the error has no position in the text
  std::string field;   // dotted path such as "bodies[2].shape.radius"; empty for syntax errors
  std::string reason;  // the message without the "FILE:LINE:COLUMN: field '...': " prefix
};

// A step that left a body's state non-finite (a NaN or an infinity): the world stops rather than
// carry NaN on. what() names the step, the body, the quantity and where the body was at the start
// of that step; the world is not usable afterwards (reset it or make a new one).
struct NonFiniteStateError : Error {
  using Error::Error;
};

// A step stopped at one of the documented limits that guard the memory (docs/reliability.md,
// "Limits"): more candidate pairs than the world allows, which means bodies overlap en masse.
// what() names the step, the count and the limit; the world is not usable afterwards.
struct StepLimitError : Error {
  using Error::Error;
};

}  // namespace tumble
