// What `moreau inspect` prints: the inventory of a recording as text or JSON.
#pragma once

#include <string>

#include "moreau/mocap/inventory.h"

namespace moreau::cli {

// Format, markers, frames, rate, duration, units and the gap table, as text on stdout.
void PrintInventory(const std::string& file, const mocap::RecordingInventory& inventory);

}  // namespace moreau::cli
