#include "support/progress_line.hpp"

#include <unistd.h>

namespace fieldlidar::app {

bool stderr_is_terminal() {
  return ::isatty(STDERR_FILENO) == 1;
}

}  // namespace fieldlidar::app
