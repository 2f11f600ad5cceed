// What every benchmark binary shares: the device, and its description in the JSON context.
#pragma once

#include <benchmark/benchmark.h>

#include "cl/device.h"

namespace sdfbrick::bench {

// The device named by $SDFBRICK_DEVICE (default: the first GPU, else device 0), opened once.
inline ocl::Device& device() {
    static ocl::DeviceSet set = ocl::DeviceSet::open("");
    return set[0];
}

// Device, vendor, driver and platform in the benchmark JSON's context.
inline void add_device_context() {
    const ocl::DeviceInfo& info = device().info();
    benchmark::AddCustomContext("device", info.name);
    benchmark::AddCustomContext("device_vendor", info.vendor);
    benchmark::AddCustomContext("driver", info.driver_version);
    benchmark::AddCustomContext("platform", info.platform_name + " " + info.platform_version);
}

}  // namespace sdfbrick::bench
