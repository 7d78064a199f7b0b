// A user program's #include lines, resolved by the library rather than by the OpenCL compiler, so
// that a program reads only files of its own folder: never an absolute path, a device or a file
// outside the folder. What the files hold becomes part of the program's source, and so of its
// program-cache key: a changed included file rebuilds the program.
#pragma once

#include <string>

namespace clraster::program {

// `source` with each `#include "path"` line replaced by that file's text, between #line directives
// so that compiler messages and parse_program name the included file and its lines. `file_name` is
// where `source` came from: its folder is the program's folder (the working directory when it names
// none). A path is relative to the folder of the file that includes it and must stay inside the
// program's folder (symbolic links are followed to check it); it names a regular file.
// Throws InvalidArgument "FILE:LINE: ..." for an #include of any other form (<...>, a macro, an
// absolute path, a path out of the folder), a file that cannot be read, includes nested deeper
// than CLR_MAX_INCLUDE_DEPTH, or sources larger than CLR_MAX_PROGRAM_SOURCE_MIB together.
std::string resolve_includes(const std::string& source, const std::string& file_name);

}  // namespace clraster::program
