#pragma once
// `crackflow verify`: runs the registered verification cases and prints a table (or JSON).
#include <string>
#include <vector>

namespace cf::runtime {

// Returns the process exit code: 0 all passed, 1 some failed, 2 unknown case name.
int verify_command(const std::vector<std::string>& case_names, bool json);

}  // namespace cf::runtime
