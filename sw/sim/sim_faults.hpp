// The sim backend's handles for injecting faults (make faults, docs/faults.md):
// the simulated system behind a device, and a lost interrupt.
#pragma once
#include "rtaccel.h"
#include "system_sim.hpp"

namespace rtaccel::sim {
// The simulated system of a device opened with rtaccel_open_sim (nullptr for another backend's).
SystemSim* systemOf(rtaccel_dev* dev);
// The device's next wait for the interrupt misses it and runs to its bound (max_cycles); false if not a sim device.
bool loseNextInterrupt(rtaccel_dev* dev);
}  // namespace rtaccel::sim
