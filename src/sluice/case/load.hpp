// Case files: TOML text to a checked Case, with every mistake a CaseError naming the file, line and
// column, the key, the value given and what was expected.
#pragma once

#include <filesystem>
#include <string>
#include <string_view>

#include "sluice/case/case.hpp"

namespace sluice {

// `source` names the text in error messages (a path, or "built-in case 'x'"); relative mesh file
// names are looked up in `mesh_directory` (empty: the built-in meshes, then the current directory).
Case parse_case(std::string_view toml_text, const std::string& source, const std::string& mesh_directory = {});
Case load_case_file(const std::filesystem::path& path);

}  // namespace sluice
