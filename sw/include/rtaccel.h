/* librtaccel: the host library of the rtaccel ray-tracing accelerator.
 *
 * One register-level driver (registers from the generated rtaccel_regs.h),
 * two backends:
 *   - "sim": the Verilated rtaccel_system in this process, with a C++ DDR model
 *     behind its m_axi port (built with the simulator, sw/sim/);
 *   - "uio": a ZC706 under Linux: the register page through UIO (or /dev/mem),
 *     the DDR buffer a physically contiguous u-dma-buf (see sw/README.md).
 *
 * The sequence (docs: /work contract "Driver sequence"): open, load a scene
 * package's image.bin, submit a batch of rays, wait, read hits and counters.
 *
 * Errors: every call returns an rtaccel_status; nothing aborts. After a
 * failure rtaccel_last_error(dev) holds a sentence naming the file, register
 * or value concerned.
 *
 * Faults (docs/faults.md): every wait is bounded (the timeout argument, or a
 * default of RTACCEL_DEFAULT_TIMEOUT_MS; the sim backend counts cycles). A
 * batch that ends with a hardware fault (AXI_ERROR, WINDOW_ERROR, watchdog
 * TIMEOUT, BROKEN) returns its error code once, after the library has reset
 * the block (CTRL.SOFT_RESET) and loaded the scene again from the device
 * buffer: the next rtaccel_submit runs normally. A lost interrupt is noticed
 * at the timeout (STATUS says the batch ended) and is not an error.
 *
 * Thread safety: every call on one device takes the device's mutex, so
 * calls from several threads are serialized and safe. One batch is in flight
 * per device: rtaccel_submit while a batch runs returns RTACCEL_ERR_BUSY.
 * rtaccel_last_error's text belongs to the device: read it in the thread
 * that got the error before another call on that device. Different devices
 * share nothing (but the sim backend keeps one Verilated system per device,
 * and Verilator models are not themselves thread-safe across devices when
 * built with --threads > 1: open one sim device per process in that case).
 */
#ifndef RTACCEL_H
#define RTACCEL_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef enum rtaccel_status {
  RTACCEL_OK = 0,
  RTACCEL_ERR_ARG = -1,         /* a null pointer or zero rays */
  RTACCEL_ERR_FILE = -2,        /* a file could not be opened or read (message names it) */
  RTACCEL_ERR_NOMEM = -3,       /* host allocation failed, or the device buffer is too small */
  RTACCEL_ERR_DEVICE = -4,      /* not an rtaccel (ID or VERSION register), or the backend failed */
  RTACCEL_ERR_SCENE = -5,       /* the hardware refused the scene: STATUS.SCENE_ERROR; see rtaccel_scene_error */
  RTACCEL_ERR_TIMEOUT = -6,     /* the host's wait bound passed with the batch or load still running (call rtaccel_abort) */
  RTACCEL_ERR_BUSY = -7,        /* a batch is in flight */
  RTACCEL_ERR_NO_SCENE = -8,    /* submit before a scene loaded */
  RTACCEL_ERR_BROKEN = -9,      /* STATUS.BROKEN: a ray was lost or duplicated (never expected) */
  RTACCEL_ERR_AXI = -10,        /* STATUS.AXI_ERROR: the memory answered a non-OKAY response */
  RTACCEL_ERR_UNSUPPORTED = -11, /* the backend is not built in, or cannot run on this machine */
  RTACCEL_ERR_ABORTED = -12,    /* the batch was ended by rtaccel_abort before all its rays were done */
  RTACCEL_ERR_WINDOW = -13,     /* STATUS.WINDOW_ERROR: an access outside the DMA window was refused */
  RTACCEL_ERR_WATCHDOG = -14,   /* STATUS.TIMEOUT: the hardware watchdog ended a batch or load without progress */
  RTACCEL_ERR_ALIGN = -15,      /* a ray or hit pointer not aligned to its record's type */
  RTACCEL_ERR_TOO_BIG = -16,    /* a batch larger than the device's ray and hit buffers, or more hits than the batch */
  RTACCEL_ERR_LAYOUT = -17,     /* a scene of another node layout than the hardware's (CONFIG_LAYOUT) */
  RTACCEL_ERR_STATE = -18       /* a call the device's state does not allow: wait or abort without a batch, hits of a
                                   batch that did not complete */
} rtaccel_status;

/* SCENE_ERROR_CODE values (contract; the hardware's scene checks). */
enum {
  RTACCEL_SCENE_OK = 0,
  RTACCEL_SCENE_BAD_MAGIC = 1,
  RTACCEL_SCENE_BAD_VERSION = 2,
  RTACCEL_SCENE_LAYOUT = 3,
  RTACCEL_SCENE_RECORD_SIZE = 4,
  RTACCEL_SCENE_MISALIGNED = 5,
  RTACCEL_SCENE_STACK_BOUND = 6
};

/* The 48-byte ray record in DDR, field for field. flags bit 0: shadow ray. */
typedef struct rtaccel_ray {
  float ox, oy, oz, dx, dy, dz, tmin, tmax;
  uint32_t flags;
  uint32_t reserved[3]; /* zero */
} rtaccel_ray;

/* The 32-byte hit record. status bit 0: hit; bits 8..: the ray's ErrorFlags. */
typedef struct rtaccel_hit {
  uint32_t number;
  uint32_t status;
  float t, u, v;
  uint32_t prim;
  uint32_t reserved[2];
} rtaccel_hit;

#define RTACCEL_HIT_FLAG 0x1u
#define RTACCEL_HIT_ERRORS(status) (((status) >> 8) & 0xffu)

/* ErrorFlags bits (src/main/scala/rtaccel/ErrorFlags.scala). */
#define RTACCEL_ERROR_FLAGS 5

/* Counters summed over the cores (64-bit registers), and per-flag error counts. */
typedef struct rtaccel_counters {
  uint64_t cycles, rays_in, hits_out, node_fetches, tri_fetches, box_tests, child_box_tests, tri_tests, decisions,
      leaf_returns, node_store_hits, node_store_misses, axi_read_beats, axi_write_beats, axi_read_stall, in_flight_sum;
  uint32_t rays_done;
  uint32_t err_count[RTACCEL_ERROR_FLAGS];
} rtaccel_counters;

/* The hardware's configuration (CONFIG_* registers). */
typedef struct rtaccel_info {
  uint32_t id, version, cores, layout, ray_ids, stack_depth, float_format, node_store_bytes, axi_data_bits;
} rtaccel_info;

/* Options of the simulation backend. Zero fields take the defaults shown. */
typedef struct rtaccel_sim_options {
  double fabric_mhz;          /* 200 */
  double ddr_bytes_per_s;     /* 12.8e9 (ZC706 PL DDR3) */
  uint32_t burst_bytes;       /* 64 */
  uint32_t latency_ns_lo;     /* 100 */
  uint32_t latency_ns_hi;     /* = lo */
  uint32_t max_outstanding;   /* 64 */
  int64_t seed;               /* 1 (the memory model's random draws: latency when lo < hi, reordering) */
  uint32_t no_reorder;        /* 0: a random done burst among IDs goes next (as the Scala AxiMemoryModel's
                                 default); 1: bursts answered in acceptance order (deterministic whatever
                                 the seed and the cycles before) */
  uint64_t max_cycles;        /* 0: no limit on a wait, else RTACCEL_ERR_TIMEOUT after this many cycles */
  const char* vcd_path;       /* NULL: no waveform (only when built with tracing) */
  uint32_t progress;          /* 0: quiet; 1: a wait lasting over 3 s shows hits written / rays of the batch,
                                 elapsed and ETA on stderr (rtaccel_progress.hpp; RTACCEL_PROGRESS=off|plain|tty) */
} rtaccel_sim_options;

typedef struct rtaccel_dev rtaccel_dev;

/* Opens the simulation backend (RTACCEL_ERR_UNSUPPORTED if this library was built without it). */
rtaccel_status rtaccel_open_sim(const rtaccel_sim_options* opt, rtaccel_dev** out);
/* Opens a board: uio_path e.g. "/dev/uio0" (registers = map 0), or "/dev/mem@0x43c00000" for
 * /dev/mem at that physical address; udmabuf_name e.g. "udmabuf0" (/dev/udmabuf0 and
 * /sys/class/u-dma-buf/udmabuf0/phys_addr, size). Linux only. */
rtaccel_status rtaccel_open_uio(const char* uio_path, const char* udmabuf_name, rtaccel_dev** out);
/* Closes and frees; null is fine. */
void rtaccel_close(rtaccel_dev* dev);

const char* rtaccel_status_name(rtaccel_status s);
/* The last failure on this device, as a sentence ("" if none). Valid until the next call on it. */
const char* rtaccel_last_error(const rtaccel_dev* dev);
/* For rtaccel_open_* failures, where no device exists: the last open failure of this thread. */
const char* rtaccel_open_error(void);

rtaccel_status rtaccel_info_get(rtaccel_dev* dev, rtaccel_info* out);

/* Copies a memory image (image.bin) to the device and loads it (CTRL.LOAD_SCENE), waiting for
 * SCENE_READY or SCENE_ERROR. RTACCEL_ERR_SCENE: rtaccel_scene_error gives SCENE_ERROR_CODE. */
rtaccel_status rtaccel_load_scene(rtaccel_dev* dev, const void* image, size_t bytes);
/* The same from a file: image.bin, or a package directory holding it. */
rtaccel_status rtaccel_load_scene_file(rtaccel_dev* dev, const char* path);
uint32_t rtaccel_scene_error(const rtaccel_dev* dev);
const char* rtaccel_scene_error_name(uint32_t code);

/* Copies `count` rays to the device and starts them (CTRL.START). Ray i's hit has number i. */
rtaccel_status rtaccel_submit(rtaccel_dev* dev, const rtaccel_ray* rays, uint32_t count);
/* Waits for the batch's end. timeout_ms: board wall time (0: RTACCEL_DEFAULT_TIMEOUT_MS); the sim
 * backend bounds a wait by rtaccel_sim_options.max_cycles instead. RTACCEL_ERR_TIMEOUT: the batch is
 * still running (rtaccel_abort ends it); a fault's code: the batch failed and the block is ready again. */
rtaccel_status rtaccel_wait(rtaccel_dev* dev, uint32_t timeout_ms);
/* Ends the running batch (CTRL.ABORT: no more rays start, the rays in flight finish), waits for it
 * (bounded by timeout_ms as rtaccel_wait), and leaves the block ready for the next batch (SOFT_RESET and a
 * scene reload if the batch does not end or ends with a fault). RTACCEL_OK: the batch ended, by itself
 * (its hits are readable) or by the abort (they are not: RTACCEL_ERR_STATE). RTACCEL_ERR_STATE without a
 * batch. */
rtaccel_status rtaccel_abort(rtaccel_dev* dev, uint32_t timeout_ms);
#define RTACCEL_DEFAULT_TIMEOUT_MS 10000u
/* Copies the batch's hits out (hit i at index i); count = the batch's ray count. */
rtaccel_status rtaccel_read_hits(rtaccel_dev* dev, rtaccel_hit* hits, uint32_t count);
rtaccel_status rtaccel_read_counters(rtaccel_dev* dev, rtaccel_counters* out);
/* Zeroes the counters (CTRL.CLEAR_COUNTERS). */
rtaccel_status rtaccel_clear_counters(rtaccel_dev* dev);

/* Simulation backend only (else RTACCEL_ERR_UNSUPPORTED): cycles simulated since open, and
 * the DDR model's statistics as a JSON object written to `path`. */
rtaccel_status rtaccel_sim_cycles(rtaccel_dev* dev, uint64_t* cycles);
rtaccel_status rtaccel_sim_write_memory_json(rtaccel_dev* dev, const char* path);
/* Simulation backend only: lets `cycles` cycles of the system pass (the board's time between two calls). */
rtaccel_status rtaccel_sim_run(rtaccel_dev* dev, uint64_t cycles);

#ifdef __cplusplus
}
#endif
#endif
