// A thin C++ wrapper of librtaccel (rtaccel.h): ownership by RAII, statuses
// returned as they are (no exceptions), hits in a std::vector.
#pragma once
#include <memory>
#include <string>
#include <vector>

#include "rtaccel.h"

namespace rtaccel {

class Device {
 public:
  static rtaccel_status openSim(const rtaccel_sim_options& o, Device& out) { return out.adopt(rtaccel_open_sim(&o, &out.raw_)); }
  static rtaccel_status openUio(const std::string& uio, const std::string& dma, Device& out) {
    return out.adopt(rtaccel_open_uio(uio.c_str(), dma.c_str(), &out.raw_));
  }
  Device() = default;
  Device(Device&& o) noexcept : raw_(o.raw_) { o.raw_ = nullptr; }
  Device& operator=(Device&& o) noexcept { std::swap(raw_, o.raw_); return *this; }
  Device(const Device&) = delete;
  Device& operator=(const Device&) = delete;
  ~Device() { rtaccel_close(raw_); }

  explicit operator bool() const { return raw_ != nullptr; }
  rtaccel_dev* raw() { return raw_; }
  std::string lastError() const { return raw_ ? rtaccel_last_error(raw_) : rtaccel_open_error(); }

  rtaccel_status loadScene(const std::string& path) { return rtaccel_load_scene_file(raw_, path.c_str()); }
  rtaccel_status loadScene(const void* image, size_t bytes) { return rtaccel_load_scene(raw_, image, bytes); }
  uint32_t sceneError() const { return rtaccel_scene_error(raw_); }
  rtaccel_status submit(const std::vector<rtaccel_ray>& rays) {
    return rtaccel_submit(raw_, rays.data(), uint32_t(rays.size()));
  }
  rtaccel_status wait(uint32_t timeoutMs = 0) { return rtaccel_wait(raw_, timeoutMs); }
  rtaccel_status hits(std::vector<rtaccel_hit>& out, uint32_t count) {
    out.resize(count);
    return rtaccel_read_hits(raw_, out.data(), count);
  }
  rtaccel_status counters(rtaccel_counters& c) { return rtaccel_read_counters(raw_, &c); }
  rtaccel_status info(rtaccel_info& i) { return rtaccel_info_get(raw_, &i); }

 private:
  rtaccel_status adopt(rtaccel_status s) { if (s != RTACCEL_OK) raw_ = nullptr; return s; }
  rtaccel_dev* raw_ = nullptr;
};

}  // namespace rtaccel
