#include "commands.hpp"

namespace navtool {

int mesh_info(const std::vector<std::string>&) { return exit_failure; }

}  // namespace navtool
