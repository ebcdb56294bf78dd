#pragma once
// Warnings to the user: on stderr, one line each, "fieldlidar: warning: ...".

#include <string>

#include "fieldlidar/io/frame_source.hpp"

namespace fieldlidar::app {

void warn(const std::string& message);

/// Prints what `source` lost without stopping (FrameSource::warnings(), e.g. a truncated
/// capture's tail); call once it has been read to the end.
void warn_source_losses(const io::FrameSource& source);

}  // namespace fieldlidar::app
