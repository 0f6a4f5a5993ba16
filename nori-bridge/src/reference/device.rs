//! Owned Embree device (RAII).

use anyhow::{bail, Result};
use embree::sys;

pub struct Device(sys::RTCDevice);

// Embree devices are thread-safe.
unsafe impl Send for Device {}
unsafe impl Sync for Device {}

impl Device {
    /// `threads`: Embree's own builder threads (0 = all cores).
    pub fn new(threads: usize) -> Result<Device> {
        let cfg = std::ffi::CString::new(format!("threads={threads}")).unwrap();
        let d = unsafe { sys::rtcNewDevice(cfg.as_ptr()) };
        if d.is_null() {
            bail!("Embree: rtcNewDevice failed (is libembree3 installed?)");
        }
        Ok(Device(d))
    }

    pub fn raw(&self) -> sys::RTCDevice {
        self.0
    }

    pub fn error(&self) -> sys::RTCError {
        unsafe { sys::rtcGetDeviceError(self.0) }
    }
}

impl Drop for Device {
    fn drop(&mut self) {
        unsafe { sys::rtcReleaseDevice(self.0) }
    }
}
