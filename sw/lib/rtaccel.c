/* The register-level driver: the contract's driver sequence over any backend. */
#define _GNU_SOURCE
#include <errno.h>
#include <pthread.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "backend.h"
#include "regs.h"

#define RAY_BYTES 48u
#define HIT_BYTES 32u
#define ALIGN 64u /* SCENE_BASE, RAY_BASE, HIT_BASE must be 64-byte aligned (contract) */

_Static_assert(sizeof(rtaccel_ray) == RAY_BYTES, "rtaccel_ray must be the 48-byte DDR record");
_Static_assert(sizeof(rtaccel_hit) == HIT_BYTES, "rtaccel_hit must be the 32-byte DDR record");

struct rtaccel_dev {
  const rtaccel_backend* be;
  void* ctx;
  pthread_mutex_t mu;
  uint64_t buf_base, buf_size;
  uint64_t scene_base;    /* where the image starts: buf_base, or after a skew that puts its nodes on a beat */
  uint64_t scene_bytes;   /* the skew and the loaded image's size (rays go after them) */
  int scene_ready;
  uint32_t scene_error;
  uint64_t ray_base, hit_base;
  uint32_t batch;         /* rays of the batch submitted last */
  int busy;
  int hits_valid;         /* the last batch completed: its hit records are all written */
  char err[512];
};

static _Thread_local char open_err[512];

void rtaccel_set_open_error(const char* fmt, ...) {
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(open_err, sizeof open_err, fmt, ap);
  va_end(ap);
}
const char* rtaccel_open_error(void) { return open_err; }

static rtaccel_status fail(rtaccel_dev* d, rtaccel_status s, const char* fmt, ...) {
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(d->err, sizeof d->err, fmt, ap);
  va_end(ap);
  return s;
}

static uint64_t align_up(uint64_t x) { return (x + ALIGN - 1) & ~(uint64_t)(ALIGN - 1); }

#define TRY(expr) do { rtaccel_status s_ = (expr); if (s_ != RTACCEL_OK) return s_; } while (0)

static rtaccel_status rd(rtaccel_dev* d, uint32_t off, uint32_t* v) {
  return d->be->reg_read(d->ctx, off, v, d->err, sizeof d->err);
}
static rtaccel_status wr(rtaccel_dev* d, uint32_t off, uint32_t v) {
  return d->be->reg_write(d->ctx, off, v, d->err, sizeof d->err);
}
/* A 64-bit counter: reading _LO latches _HI. */
static rtaccel_status rd64(rtaccel_dev* d, uint32_t lo_off, uint32_t hi_off, uint64_t* v) {
  uint32_t lo, hi;
  TRY(rd(d, lo_off, &lo));
  TRY(rd(d, hi_off, &hi));
  *v = ((uint64_t)hi << 32) | lo;
  return RTACCEL_OK;
}

const char* rtaccel_status_name(rtaccel_status s) {
  switch (s) {
    case RTACCEL_OK: return "RTACCEL_OK";
    case RTACCEL_ERR_ARG: return "RTACCEL_ERR_ARG";
    case RTACCEL_ERR_FILE: return "RTACCEL_ERR_FILE";
    case RTACCEL_ERR_NOMEM: return "RTACCEL_ERR_NOMEM";
    case RTACCEL_ERR_DEVICE: return "RTACCEL_ERR_DEVICE";
    case RTACCEL_ERR_SCENE: return "RTACCEL_ERR_SCENE";
    case RTACCEL_ERR_TIMEOUT: return "RTACCEL_ERR_TIMEOUT";
    case RTACCEL_ERR_BUSY: return "RTACCEL_ERR_BUSY";
    case RTACCEL_ERR_NO_SCENE: return "RTACCEL_ERR_NO_SCENE";
    case RTACCEL_ERR_BROKEN: return "RTACCEL_ERR_BROKEN";
    case RTACCEL_ERR_AXI: return "RTACCEL_ERR_AXI";
    case RTACCEL_ERR_UNSUPPORTED: return "RTACCEL_ERR_UNSUPPORTED";
    case RTACCEL_ERR_ABORTED: return "RTACCEL_ERR_ABORTED";
    case RTACCEL_ERR_WINDOW: return "RTACCEL_ERR_WINDOW";
    case RTACCEL_ERR_WATCHDOG: return "RTACCEL_ERR_WATCHDOG";
    case RTACCEL_ERR_ALIGN: return "RTACCEL_ERR_ALIGN";
    case RTACCEL_ERR_TOO_BIG: return "RTACCEL_ERR_TOO_BIG";
    case RTACCEL_ERR_LAYOUT: return "RTACCEL_ERR_LAYOUT";
    case RTACCEL_ERR_STATE: return "RTACCEL_ERR_STATE";
  }
  return "RTACCEL_ERR_UNKNOWN";
}

const char* rtaccel_scene_error_name(uint32_t code) {
  static const char* names[] = {"none", "bad magic", "bad version", "layout differs from the hardware's",
                                "nodeBytes/triBytes differ from the hardware's", "misaligned base",
                                "stack bound (bvhDepth) exceeds the hardware stack depth"};
  return code < sizeof names / sizeof names[0] ? names[code] : "unknown scene error code";
}

rtaccel_status rtaccel_attach(const rtaccel_backend* be, void* ctx, uint64_t buf_base, uint64_t buf_size,
                              rtaccel_dev** out) {
  rtaccel_dev* d = calloc(1, sizeof *d);
  if (!d) {
    be->close(ctx);
    rtaccel_set_open_error("rtaccel: out of host memory");
    return RTACCEL_ERR_NOMEM;
  }
  d->be = be;
  d->ctx = ctx;
  d->buf_base = buf_base;
  d->buf_size = buf_size;
  pthread_mutex_init(&d->mu, NULL);
  if (buf_base % ALIGN != 0) {
    rtaccel_set_open_error("rtaccel %s: device buffer at 0x%llx is not 64-byte aligned", be->name,
                           (unsigned long long)buf_base);
    rtaccel_close(d);
    return RTACCEL_ERR_DEVICE;
  }
  uint32_t id = 0, version = 0;
  rtaccel_status s = rd(d, RTACCEL_ID_OFFSET, &id);
  if (s == RTACCEL_OK) s = rd(d, RTACCEL_VERSION_OFFSET, &version);
  if (s == RTACCEL_OK && (id != RTACCEL_ID_VALUE || version != RTACCEL_VERSION_VALUE)) {
    snprintf(d->err, sizeof d->err, "rtaccel %s: ID 0x%08x VERSION %u: not an rtaccel of register map version %u "
             "(expected ID 0x%08x)", be->name, id, version, RTACCEL_VERSION_VALUE, RTACCEL_ID_VALUE);
    s = RTACCEL_ERR_DEVICE;
  }
  if (s != RTACCEL_OK) {
    rtaccel_set_open_error("%s", d->err);
    rtaccel_close(d);
    return s;
  }
  *out = d;
  return RTACCEL_OK;
}

void rtaccel_close(rtaccel_dev* d) {
  if (!d) return;
  d->be->close(d->ctx);
  pthread_mutex_destroy(&d->mu);
  free(d);
}

const char* rtaccel_last_error(const rtaccel_dev* d) { return d ? d->err : open_err; }
uint32_t rtaccel_scene_error(const rtaccel_dev* d) { return d ? d->scene_error : 0; }

#define LOCKED(d, call)                 \
  do {                                  \
    if (!(d)) return RTACCEL_ERR_ARG;   \
    pthread_mutex_lock(&(d)->mu);       \
    (d)->err[0] = 0;                    \
    rtaccel_status r_ = (call);         \
    pthread_mutex_unlock(&(d)->mu);     \
    return r_;                          \
  } while (0)

static rtaccel_status info_locked(rtaccel_dev* d, rtaccel_info* o) {
  TRY(rd(d, RTACCEL_ID_OFFSET, &o->id));
  TRY(rd(d, RTACCEL_VERSION_OFFSET, &o->version));
  TRY(rd(d, RTACCEL_CONFIG_CORES_OFFSET, &o->cores));
  TRY(rd(d, RTACCEL_CONFIG_LAYOUT_OFFSET, &o->layout));
  TRY(rd(d, RTACCEL_CONFIG_RAY_IDS_OFFSET, &o->ray_ids));
  TRY(rd(d, RTACCEL_CONFIG_STACK_DEPTH_OFFSET, &o->stack_depth));
  TRY(rd(d, RTACCEL_CONFIG_FLOAT_OFFSET, &o->float_format));
  TRY(rd(d, RTACCEL_CONFIG_NODE_STORE_BYTES_OFFSET, &o->node_store_bytes));
  TRY(rd(d, RTACCEL_CONFIG_AXI_DATA_BITS_OFFSET, &o->axi_data_bits));
  return RTACCEL_OK;
}
rtaccel_status rtaccel_info_get(rtaccel_dev* d, rtaccel_info* o) {
  if (!o) return RTACCEL_ERR_ARG;
  LOCKED(d, info_locked(d, o));
}

/* The sticky STATUS faults that only SOFT_RESET clears. */
#define FAULT_MASK \
  (RTACCEL_STATUS_BROKEN_MASK | RTACCEL_STATUS_AXI_ERROR_MASK | RTACCEL_STATUS_TIMEOUT_MASK | RTACCEL_STATUS_WINDOW_ERROR_MASK)

/* STATUS bits that end a wait badly, whatever the operation. */
static rtaccel_status check_sticky(rtaccel_dev* d, uint32_t status) {
  if (status & RTACCEL_STATUS_BROKEN_MASK)
    return fail(d, RTACCEL_ERR_BROKEN, "rtaccel: STATUS.BROKEN (0x%08x): the hardware lost or duplicated a ray", status);
  if (status & RTACCEL_STATUS_WINDOW_ERROR_MASK) {
    uint32_t addr = 0;
    rd(d, RTACCEL_WINDOW_FAULT_ADDR_OFFSET, &addr);
    return fail(d, RTACCEL_ERR_WINDOW, "rtaccel: STATUS.WINDOW_ERROR (0x%08x): an access at 0x%08x outside the DMA window "
                "was refused", status, addr);
  }
  if (status & RTACCEL_STATUS_AXI_ERROR_MASK)
    return fail(d, RTACCEL_ERR_AXI, "rtaccel: STATUS.AXI_ERROR (0x%08x): the memory answered a non-OKAY response "
                "(an address outside the device buffer?)", status);
  if (status & RTACCEL_STATUS_TIMEOUT_MASK)
    return fail(d, RTACCEL_ERR_WATCHDOG, "rtaccel: STATUS.TIMEOUT (0x%08x): the watchdog ended the batch after "
                "WATCHDOG_CYCLES cycles without progress (a memory response that never came?)", status);
  return RTACCEL_OK;
}

static rtaccel_status load_scene_hw(rtaccel_dev* d);

/* After a fault: SOFT_RESET, then the scene loaded again from the device buffer (it is still there). The
   fault's own message stays in d->err unless the recovery itself fails. */
static rtaccel_status recover(rtaccel_dev* d) {
  char why[sizeof d->err];
  memcpy(why, d->err, sizeof why);
  d->busy = 0;
  d->hits_valid = 0;
  TRY(wr(d, RTACCEL_CTRL_OFFSET, RTACCEL_CTRL_SOFT_RESET_MASK));
  int had_scene = d->scene_ready;
  d->scene_ready = 0;
  if (had_scene) {
    rtaccel_status s = load_scene_hw(d);
    if (s != RTACCEL_OK) {
      char again[sizeof d->err];
      memcpy(again, d->err, sizeof again);
      return fail(d, s, "%s; then reloading the scene after SOFT_RESET failed: %s", why, again);
    }
  }
  memcpy(d->err, why, sizeof why);
  return RTACCEL_OK;
}

/* A little-endian 32-bit word of the scene image. */
static uint32_t le32(const uint8_t* p) { return p[0] | p[1] << 8 | p[2] << 16 | (uint32_t)p[3] << 24; }

static rtaccel_status load_locked(rtaccel_dev* d, const void* image, size_t bytes) {
  if (d->busy) return fail(d, RTACCEL_ERR_BUSY, "rtaccel: a batch is in flight; wait for it before loading a scene");
  if (bytes < 64) return fail(d, RTACCEL_ERR_ARG, "rtaccel: a %zu-byte image is shorter than its 64-byte header", bytes);
  if (bytes > d->buf_size)
    return fail(d, RTACCEL_ERR_NOMEM, "rtaccel: the %zu-byte image does not fit the %llu-byte device buffer", bytes,
                (unsigned long long)d->buf_size);
  d->scene_ready = 0;
  d->scene_error = 0;
  d->scene_bytes = 0;
  /* The node array (header bytes 20..23: nodeOffset, 64-byte aligned) starts on an m_axi beat: with a beat wider
     than the contract's 64-byte alignment (a 1024-bit system) a node then never straddles two beats, which would
     cost a second beat and two more DDR lines per node read (docs/system-wide.md). 0 for a 512-bit system. */
  /* The simulation gives the width without an s_axi access, so its cycles before START (and its DDR model's
     random draws) stay as they were; the board reads the register. */
  uint32_t axi_bits;
  if (d->be->sim_axi_data_bits) axi_bits = d->be->sim_axi_data_bits(d->ctx);
  else TRY(rd(d, RTACCEL_CONFIG_AXI_DATA_BITS_OFFSET, &axi_bits));
  /* header words 20..23 nodeOffset, 24..27 triOffset (docs/memory-format.md), little-endian */
  const uint8_t* hdr = image;
  const uint32_t node_off = le32(hdr + 20), tri_off = le32(hdr + 24);
  uint32_t beat = axi_bits / 8;
  uint64_t skew = beat > ALIGN ? (beat - node_off % beat) % beat : 0;
  if (skew % ALIGN != 0 || bytes + skew > d->buf_size) skew = 0; /* keep the contract's alignment; never past the buffer */
  d->scene_base = d->buf_base + skew;
  TRY(d->be->mem_write(d->ctx, d->scene_base, image, bytes, d->err, sizeof d->err));
  TRY(load_scene_hw(d));
  d->scene_bytes = skew + bytes;
  if (d->be->sim_region) {
    if (node_off <= tri_off && tri_off <= bytes) {
      d->be->sim_region(d->ctx, "header", d->scene_base, d->scene_base + node_off);
      d->be->sim_region(d->ctx, "nodes", d->scene_base + node_off, d->scene_base + tri_off);
      d->be->sim_region(d->ctx, "triangles", d->scene_base + tri_off, d->scene_base + bytes);
    }
  }
  return RTACCEL_OK;
}

/* LOAD_SCENE of the image at d->scene_base, waiting (bounded) for SCENE_READY or SCENE_ERROR. */
static rtaccel_status load_scene_hw(rtaccel_dev* d) {
  TRY(wr(d, RTACCEL_SCENE_BASE_OFFSET, (uint32_t)d->scene_base));
  TRY(wr(d, RTACCEL_IRQ_STATUS_OFFSET, RTACCEL_IRQ_STATUS_SCENE_MASK | RTACCEL_IRQ_STATUS_DONE_MASK | RTACCEL_IRQ_STATUS_FAULT_MASK));
  TRY(wr(d, RTACCEL_IRQ_ENABLE_OFFSET, RTACCEL_IRQ_ENABLE_SCENE_MASK | RTACCEL_IRQ_ENABLE_FAULT_MASK));
  TRY(wr(d, RTACCEL_CTRL_OFFSET, RTACCEL_CTRL_LOAD_SCENE_MASK));
  rtaccel_status w = d->be->wait_irq(d->ctx, RTACCEL_DEFAULT_TIMEOUT_MS, d->err, sizeof d->err);
  uint32_t status = 0;
  if (w == RTACCEL_ERR_TIMEOUT) {
    /* A lost interrupt: the load ended all the same (STATUS says so). */
    TRY(rd(d, RTACCEL_STATUS_OFFSET, &status));
    if (status & RTACCEL_STATUS_BUSY_MASK) {
      fail(d, w, "rtaccel: no SCENE interrupt after LOAD_SCENE, STATUS 0x%08x still BUSY (%s)", status, d->err);
      TRY(recover(d));
      return w;
    }
  } else {
    TRY(w);
  }
  TRY(wr(d, RTACCEL_IRQ_STATUS_OFFSET, RTACCEL_IRQ_STATUS_SCENE_MASK | RTACCEL_IRQ_STATUS_FAULT_MASK));
  TRY(rd(d, RTACCEL_STATUS_OFFSET, &status));
  rtaccel_status f = check_sticky(d, status);
  if (f != RTACCEL_OK) {
    TRY(recover(d));
    return f;
  }
  if (status & RTACCEL_STATUS_SCENE_ERROR_MASK) {
    TRY(rd(d, RTACCEL_SCENE_ERROR_CODE_OFFSET, &d->scene_error));
    return fail(d, d->scene_error == RTACCEL_SCENE_LAYOUT ? RTACCEL_ERR_LAYOUT : RTACCEL_ERR_SCENE,
                "rtaccel: the hardware refused the scene: SCENE_ERROR_CODE %u (%s)", d->scene_error,
                rtaccel_scene_error_name(d->scene_error));
  }
  if (!(status & RTACCEL_STATUS_SCENE_READY_MASK))
    return fail(d, RTACCEL_ERR_DEVICE, "rtaccel: SCENE interrupt but STATUS 0x%08x has neither SCENE_READY nor SCENE_ERROR",
                status);
  d->scene_ready = 1;
  return RTACCEL_OK;
}
rtaccel_status rtaccel_load_scene(rtaccel_dev* d, const void* image, size_t bytes) {
  if (!image) return RTACCEL_ERR_ARG;
  LOCKED(d, load_locked(d, image, bytes));
}

/* Reads a whole file; on failure a sentence naming it. */
static rtaccel_status read_file(rtaccel_dev* d, const char* path, void** data, size_t* bytes) {
  FILE* f = fopen(path, "rb");
  if (!f) return fail(d, RTACCEL_ERR_FILE, "%s: cannot open: %s", path, strerror(errno));
  struct stat st;
  if (fstat(fileno(f), &st) != 0 || !S_ISREG(st.st_mode)) {
    fclose(f);
    return fail(d, RTACCEL_ERR_FILE, "%s: not a regular file", path);
  }
  void* buf = malloc(st.st_size ? (size_t)st.st_size : 1);
  if (!buf) {
    fclose(f);
    return fail(d, RTACCEL_ERR_NOMEM, "%s: no host memory for its %lld bytes", path, (long long)st.st_size);
  }
  size_t n = fread(buf, 1, (size_t)st.st_size, f);
  int bad = ferror(f);
  fclose(f);
  if (bad || n != (size_t)st.st_size) {
    free(buf);
    return fail(d, RTACCEL_ERR_FILE, "%s: read %zu of %lld bytes", path, n, (long long)st.st_size);
  }
  *data = buf;
  *bytes = n;
  return RTACCEL_OK;
}

static rtaccel_status load_file_locked(rtaccel_dev* d, const char* path) {
  char full[4096];
  struct stat st;
  if (stat(path, &st) == 0 && S_ISDIR(st.st_mode)) snprintf(full, sizeof full, "%s/image.bin", path);
  else snprintf(full, sizeof full, "%s", path);
  void* data = NULL;
  size_t bytes = 0;
  TRY(read_file(d, full, &data, &bytes));
  static const char magic[8] = {'R', 'T', 'A', 'C', 'C', 'E', 'L', 0};
  rtaccel_status s;
  if (bytes < 64 || memcmp(data, magic, 8) != 0)
    s = fail(d, RTACCEL_ERR_FILE, "%s: not an rtaccel memory image (%zu bytes; expected the 64-byte header starting "
             "with magic RTACCEL\\0, as nori-bridge compile writes)", full, bytes);
  else
    s = load_locked(d, data, bytes);
  free(data);
  return s;
}
rtaccel_status rtaccel_load_scene_file(rtaccel_dev* d, const char* path) {
  if (!path) return RTACCEL_ERR_ARG;
  LOCKED(d, load_file_locked(d, path));
}

static rtaccel_status submit_locked(rtaccel_dev* d, const rtaccel_ray* rays, uint32_t count) {
  if (d->busy) return fail(d, RTACCEL_ERR_BUSY, "rtaccel: a batch of %u rays is in flight", d->batch);
  if (!d->scene_ready) return fail(d, RTACCEL_ERR_NO_SCENE, "rtaccel: submit before a scene loaded");
  if (count == 0) return fail(d, RTACCEL_ERR_ARG, "rtaccel: a batch of 0 rays");
  uint64_t ray_base = d->buf_base + align_up(d->scene_bytes);
  uint64_t hit_base = align_up(ray_base + (uint64_t)count * RAY_BYTES);
  uint64_t end = hit_base + (uint64_t)count * HIT_BYTES;
  if (end > d->buf_base + d->buf_size)
    return fail(d, RTACCEL_ERR_TOO_BIG, "rtaccel: %u rays need %llu bytes of device buffer after the scene; it holds %llu",
                count, (unsigned long long)(end - ray_base), (unsigned long long)(d->buf_base + d->buf_size - ray_base));
  TRY(d->be->mem_write(d->ctx, ray_base, rays, (size_t)count * RAY_BYTES, d->err, sizeof d->err));
  TRY(wr(d, RTACCEL_RAY_BASE_OFFSET, (uint32_t)ray_base));
  TRY(wr(d, RTACCEL_RAY_COUNT_OFFSET, count));
  TRY(wr(d, RTACCEL_HIT_BASE_OFFSET, (uint32_t)hit_base));
  TRY(wr(d, RTACCEL_IRQ_STATUS_OFFSET, RTACCEL_IRQ_STATUS_DONE_MASK | RTACCEL_IRQ_STATUS_FAULT_MASK));
  TRY(wr(d, RTACCEL_IRQ_ENABLE_OFFSET, RTACCEL_IRQ_ENABLE_DONE_MASK | RTACCEL_IRQ_ENABLE_FAULT_MASK));
  if (d->be->sim_region) {
    d->be->sim_region(d->ctx, "rays", ray_base, ray_base + (uint64_t)count * RAY_BYTES);
    d->be->sim_region(d->ctx, "hits", hit_base, end);
  }
  if (d->be->sim_batch_start) d->be->sim_batch_start(d->ctx);
  TRY(wr(d, RTACCEL_CTRL_OFFSET, RTACCEL_CTRL_START_MASK));
  d->ray_base = ray_base;
  d->hit_base = hit_base;
  d->batch = count;
  d->busy = 1;
  d->hits_valid = 0;
  return RTACCEL_OK;
}
rtaccel_status rtaccel_submit(rtaccel_dev* d, const rtaccel_ray* rays, uint32_t count) {
  if (!rays) return RTACCEL_ERR_ARG;
  if ((uintptr_t)rays % _Alignof(rtaccel_ray) != 0) return RTACCEL_ERR_ALIGN;
  LOCKED(d, submit_locked(d, rays, count));
}

/* The batch's end, once the interrupt came or the wait's bound passed: STATUS decides. `aborting`: the
   caller asked for ABORT, so an ABORTED end is what it wanted. */
static rtaccel_status batch_end(rtaccel_dev* d, rtaccel_status w, int aborting) {
  uint32_t status = 0;
  TRY(rd(d, RTACCEL_STATUS_OFFSET, &status));
  if (w == RTACCEL_ERR_TIMEOUT && (status & RTACCEL_STATUS_BUSY_MASK))
    return fail(d, w, "rtaccel: the batch of %u rays still runs (STATUS 0x%08x) after the wait's bound: %s; "
                "rtaccel_abort ends it", d->batch, status, d->err);
  if (w != RTACCEL_OK && w != RTACCEL_ERR_TIMEOUT) return w;
  /* Ended: with its interrupt, or with the interrupt lost (w == TIMEOUT, not BUSY). */
  TRY(wr(d, RTACCEL_IRQ_STATUS_OFFSET, RTACCEL_IRQ_STATUS_DONE_MASK | RTACCEL_IRQ_STATUS_FAULT_MASK));
  d->busy = 0;
  rtaccel_status f = check_sticky(d, status);
  if (f != RTACCEL_OK) {
    TRY(recover(d));
    return aborting ? RTACCEL_OK : f;
  }
  if (status & RTACCEL_STATUS_ABORTED_MASK)
    return aborting ? RTACCEL_OK : fail(d, RTACCEL_ERR_ABORTED, "rtaccel: the batch was aborted (STATUS 0x%08x)", status);
  if (!(status & RTACCEL_STATUS_DONE_MASK))
    return fail(d, RTACCEL_ERR_DEVICE, "rtaccel: the batch ended but STATUS 0x%08x lacks DONE", status);
  uint32_t done;
  TRY(rd(d, RTACCEL_RAYS_DONE_OFFSET, &done));
  if (done != d->batch)
    return fail(d, RTACCEL_ERR_BROKEN, "rtaccel: DONE with RAYS_DONE %u for a batch of %u rays", done, d->batch);
  d->hits_valid = 1;
  return RTACCEL_OK;
}

static rtaccel_status wait_locked(rtaccel_dev* d, uint32_t timeout_ms) {
  if (!d->busy) return fail(d, RTACCEL_ERR_STATE, "rtaccel: wait without a batch submitted");
  rtaccel_status w = d->be->wait_irq(d->ctx, timeout_ms ? timeout_ms : RTACCEL_DEFAULT_TIMEOUT_MS, d->err, sizeof d->err);
  return batch_end(d, w, 0);
}
rtaccel_status rtaccel_wait(rtaccel_dev* d, uint32_t timeout_ms) { LOCKED(d, wait_locked(d, timeout_ms)); }

static rtaccel_status abort_locked(rtaccel_dev* d, uint32_t timeout_ms) {
  if (!d->busy) return fail(d, RTACCEL_ERR_STATE, "rtaccel: abort without a batch submitted");
  TRY(wr(d, RTACCEL_CTRL_OFFSET, RTACCEL_CTRL_ABORT_MASK));
  rtaccel_status w = d->be->wait_irq(d->ctx, timeout_ms ? timeout_ms : RTACCEL_DEFAULT_TIMEOUT_MS, d->err, sizeof d->err);
  rtaccel_status s = batch_end(d, w, 1);
  /* Still running after ABORT and the wait (the watchdog disabled, or a bound shorter than it): reset. */
  if (s == RTACCEL_ERR_TIMEOUT) return recover(d);
  return s;
}
rtaccel_status rtaccel_abort(rtaccel_dev* d, uint32_t timeout_ms) { LOCKED(d, abort_locked(d, timeout_ms)); }

static rtaccel_status hits_locked(rtaccel_dev* d, rtaccel_hit* hits, uint32_t count) {
  if (d->busy) return fail(d, RTACCEL_ERR_BUSY, "rtaccel: read_hits before the batch finished (call rtaccel_wait)");
  if (!d->hits_valid)
    return fail(d, RTACCEL_ERR_STATE, "rtaccel: no hits: the last batch did not complete (aborted, failed, or none)");
  if (count > d->batch) return fail(d, RTACCEL_ERR_TOO_BIG, "rtaccel: %u hits asked of a batch of %u", count, d->batch);
  return d->be->mem_read(d->ctx, d->hit_base, hits, (size_t)count * HIT_BYTES, d->err, sizeof d->err);
}
rtaccel_status rtaccel_read_hits(rtaccel_dev* d, rtaccel_hit* hits, uint32_t count) {
  if (!hits) return RTACCEL_ERR_ARG;
  if ((uintptr_t)hits % _Alignof(rtaccel_hit) != 0) return RTACCEL_ERR_ALIGN;
  LOCKED(d, hits_locked(d, hits, count));
}

static rtaccel_status counters_locked(rtaccel_dev* d, rtaccel_counters* c) {
#define C64(field, NAME) TRY(rd64(d, RTACCEL_##NAME##_LO_OFFSET, RTACCEL_##NAME##_HI_OFFSET, &c->field))
  C64(cycles, CYCLES); C64(rays_in, RAYS_IN); C64(hits_out, HITS_OUT); C64(node_fetches, NODE_FETCHES);
  C64(tri_fetches, TRI_FETCHES); C64(box_tests, BOX_TESTS); C64(child_box_tests, CHILD_BOX_TESTS);
  C64(tri_tests, TRI_TESTS); C64(decisions, DECISIONS); C64(leaf_returns, LEAF_RETURNS);
  C64(node_store_hits, NODE_STORE_HITS); C64(node_store_misses, NODE_STORE_MISSES);
  C64(axi_read_beats, AXI_READ_BEATS); C64(axi_write_beats, AXI_WRITE_BEATS); C64(axi_read_stall, AXI_READ_STALL);
  C64(in_flight_sum, IN_FLIGHT_SUM);
#undef C64
  TRY(rd(d, RTACCEL_RAYS_DONE_OFFSET, &c->rays_done));
  TRY(rd(d, RTACCEL_ERR_COUNT_STACK_OVERFLOW_OFFSET, &c->err_count[0]));
  TRY(rd(d, RTACCEL_ERR_COUNT_INDEX_OVERFLOW_OFFSET, &c->err_count[1]));
  TRY(rd(d, RTACCEL_ERR_COUNT_LEAF_TOO_BIG_OFFSET, &c->err_count[2]));
  TRY(rd(d, RTACCEL_ERR_COUNT_INVALID_RAY_OFFSET, &c->err_count[3]));
  TRY(rd(d, RTACCEL_ERR_COUNT_BAD_SCENE_DATA_OFFSET, &c->err_count[4]));
  return RTACCEL_OK;
}
rtaccel_status rtaccel_read_counters(rtaccel_dev* d, rtaccel_counters* c) {
  if (!c) return RTACCEL_ERR_ARG;
  LOCKED(d, counters_locked(d, c));
}

rtaccel_status rtaccel_clear_counters(rtaccel_dev* d) {
  LOCKED(d, wr(d, RTACCEL_CTRL_OFFSET, RTACCEL_CTRL_CLEAR_COUNTERS_MASK));
}

static rtaccel_status sim_cycles_locked(rtaccel_dev* d, uint64_t* cycles) {
  if (!d->be->sim_cycles) return fail(d, RTACCEL_ERR_UNSUPPORTED, "rtaccel %s: not a simulation", d->be->name);
  return d->be->sim_cycles(d->ctx, cycles);
}
rtaccel_status rtaccel_sim_cycles(rtaccel_dev* d, uint64_t* cycles) {
  if (!cycles) return RTACCEL_ERR_ARG;
  LOCKED(d, sim_cycles_locked(d, cycles));
}
static rtaccel_status sim_json_locked(rtaccel_dev* d, const char* path) {
  if (!d->be->sim_memory_json) return fail(d, RTACCEL_ERR_UNSUPPORTED, "rtaccel %s: not a simulation", d->be->name);
  return d->be->sim_memory_json(d->ctx, path, d->err, sizeof d->err);
}
rtaccel_status rtaccel_sim_write_memory_json(rtaccel_dev* d, const char* path) {
  if (!path) return RTACCEL_ERR_ARG;
  LOCKED(d, sim_json_locked(d, path));
}

static rtaccel_status sim_run_locked(rtaccel_dev* d, uint64_t cycles) {
  if (!d->be->sim_run) return fail(d, RTACCEL_ERR_UNSUPPORTED, "rtaccel %s: not a simulation", d->be->name);
  return d->be->sim_run(d->ctx, cycles, d->err, sizeof d->err);
}
rtaccel_status rtaccel_sim_run(rtaccel_dev* d, uint64_t cycles) { LOCKED(d, sim_run_locked(d, cycles)); }

void* rtaccel_backend_context(rtaccel_dev* d, const rtaccel_backend* be) { return d && d->be == be ? d->ctx : NULL; }
