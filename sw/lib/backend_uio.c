/* librtaccel's board backend: a ZC706 under Linux. Compiles here; cannot run
 * here (no board). See sw/README.md for the assumptions:
 *   registers: the s_axi page through UIO ("/dev/uioN", map 0, interrupt via
 *     read() on the device, uio_pdrv_genirq) or /dev/mem ("/dev/mem@0xADDR",
 *     no interrupt: IRQ_STATUS & IRQ_ENABLE is polled);
 *   buffer: physically contiguous memory the accelerator's m_axi reaches at
 *     the same address the CPU uses: a u-dma-buf ("udmabuf0": /dev/udmabuf0
 *     opened O_SYNC, i.e. uncached, so no cache maintenance is needed), or a
 *     reserved-memory region through /dev/mem ("/dev/mem@CPU_PHYS:SIZE[:DEV_ADDR]",
 *     DEV_ADDR the address m_axi sees when it differs, e.g. PL DDR behind a MIG).
 */
#define _GNU_SOURCE
#include <errno.h>
#include <fcntl.h>
#include <poll.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <time.h>
#include <unistd.h>

#include "backend.h"
#include "regs.h"

#define REG_SPACE 4096u

typedef struct uio_ctx {
  int reg_fd, irq_fd; /* irq_fd: the UIO device, or -1 (poll registers) */
  volatile uint32_t* regs;
  int buf_fd;
  uint8_t* buf;
  uint64_t buf_dev, buf_size;
} uio_ctx;

static rtaccel_status reg_read(void* c, uint32_t off, uint32_t* v, char* err, size_t errn) {
  uio_ctx* x = c;
  if (off >= REG_SPACE || off % 4) { snprintf(err, errn, "rtaccel uio: register offset 0x%x", off); return RTACCEL_ERR_ARG; }
  *v = x->regs[off / 4];
  return RTACCEL_OK;
}
static rtaccel_status reg_write(void* c, uint32_t off, uint32_t v, char* err, size_t errn) {
  uio_ctx* x = c;
  if (off >= REG_SPACE || off % 4) { snprintf(err, errn, "rtaccel uio: register offset 0x%x", off); return RTACCEL_ERR_ARG; }
  x->regs[off / 4] = v;
  __sync_synchronize(); /* the store reaches the device before a later load is issued */
  return RTACCEL_OK;
}
static rtaccel_status window(uio_ctx* x, uint64_t addr, size_t n, char* err, size_t errn) {
  if (addr < x->buf_dev || addr + n > x->buf_dev + x->buf_size) {
    snprintf(err, errn, "rtaccel uio: %zu bytes at 0x%llx lie outside the DMA buffer", n, (unsigned long long)addr);
    return RTACCEL_ERR_ARG;
  }
  return RTACCEL_OK;
}
static rtaccel_status mem_write(void* c, uint64_t addr, const void* src, size_t n, char* err, size_t errn) {
  uio_ctx* x = c;
  rtaccel_status s = window(x, addr, n, err, errn);
  if (s == RTACCEL_OK) { memcpy(x->buf + (addr - x->buf_dev), src, n); __sync_synchronize(); }
  return s;
}
static rtaccel_status mem_read(void* c, uint64_t addr, void* dst, size_t n, char* err, size_t errn) {
  uio_ctx* x = c;
  rtaccel_status s = window(x, addr, n, err, errn);
  if (s == RTACCEL_OK) { __sync_synchronize(); memcpy(dst, x->buf + (addr - x->buf_dev), n); }
  return s;
}
static uint64_t now_ms(void) {
  struct timespec t;
  clock_gettime(CLOCK_MONOTONIC, &t);
  return (uint64_t)t.tv_sec * 1000 + (uint64_t)t.tv_nsec / 1000000;
}
static rtaccel_status wait_irq(void* c, uint32_t timeout_ms, char* err, size_t errn) {
  uio_ctx* x = c;
  uint64_t end = now_ms() + timeout_ms;
  for (;;) {
    if (x->regs[RTACCEL_IRQ_STATUS_OFFSET / 4] & x->regs[RTACCEL_IRQ_ENABLE_OFFSET / 4]) return RTACCEL_OK;
    uint64_t t = now_ms();
    if (timeout_ms && t >= end) { snprintf(err, errn, "%u ms passed", timeout_ms); return RTACCEL_ERR_TIMEOUT; }
    if (x->irq_fd >= 0) {
      uint32_t one = 1, count;
      /* uio_pdrv_genirq: writing 1 re-enables the interrupt; read() returns its event count. */
      if (write(x->irq_fd, &one, sizeof one) != (ssize_t)sizeof one) {
        snprintf(err, errn, "rtaccel uio: unmask interrupt: %s", strerror(errno));
        return RTACCEL_ERR_DEVICE;
      }
      struct pollfd p = {x->irq_fd, POLLIN, 0};
      int r = poll(&p, 1, timeout_ms ? (int)(end - t) : 100);
      if (r > 0 && read(x->irq_fd, &count, sizeof count) != (ssize_t)sizeof count) {
        snprintf(err, errn, "rtaccel uio: read interrupt: %s", strerror(errno));
        return RTACCEL_ERR_DEVICE;
      }
    } else {
      struct timespec nap = {0, 20000}; /* 20 us between polls of IRQ_STATUS */
      nanosleep(&nap, NULL);
    }
  }
}
static void close_ctx(void* c) {
  uio_ctx* x = c;
  if (x->regs) munmap((void*)x->regs, REG_SPACE);
  if (x->buf) munmap(x->buf, x->buf_size);
  if (x->reg_fd >= 0) close(x->reg_fd);
  if (x->buf_fd >= 0) close(x->buf_fd);
  free(x);
}

static const rtaccel_backend uio_backend = {"uio", reg_read, reg_write, mem_write, mem_read, wait_irq, NULL, NULL, NULL, NULL, close_ctx, NULL,
                                            NULL};

static int read_sysfs_u64(const char* path, uint64_t* v) {
  FILE* f = fopen(path, "r");
  if (!f) return -1;
  unsigned long long x;
  int ok = fscanf(f, "%lli", (long long*)&x) == 1;
  fclose(f);
  *v = x;
  return ok ? 0 : -1;
}

static rtaccel_status open_fail(uio_ctx* x, rtaccel_status s) { close_ctx(x); return s; }

rtaccel_status rtaccel_open_uio(const char* uio_path, const char* dma, rtaccel_dev** out) {
  if (!uio_path || !dma || !out) return RTACCEL_ERR_ARG;
  uio_ctx* x = calloc(1, sizeof *x);
  if (!x) return RTACCEL_ERR_NOMEM;
  x->reg_fd = x->buf_fd = x->irq_fd = -1;
  unsigned long long reg_phys = 0;
  int devmem = sscanf(uio_path, "/dev/mem@%lli", (long long*)&reg_phys) == 1;
  x->reg_fd = open(devmem ? "/dev/mem" : uio_path, O_RDWR | O_SYNC);
  if (x->reg_fd < 0) {
    rtaccel_set_open_error("%s: cannot open: %s", devmem ? "/dev/mem" : uio_path, strerror(errno));
    return open_fail(x, RTACCEL_ERR_FILE);
  }
  /* UIO: map N lies at offset N * page size; the registers are map 0. */
  void* r = mmap(NULL, REG_SPACE, PROT_READ | PROT_WRITE, MAP_SHARED, x->reg_fd, devmem ? (off_t)reg_phys : 0);
  if (r == MAP_FAILED) {
    rtaccel_set_open_error("%s: mmap of the register page: %s", uio_path, strerror(errno));
    return open_fail(x, RTACCEL_ERR_DEVICE);
  }
  x->regs = r;
  if (!devmem) x->irq_fd = x->reg_fd;

  unsigned long long cpu_phys = 0, size = 0, dev_addr = 0;
  int n = sscanf(dma, "/dev/mem@%lli:%lli:%lli", (long long*)&cpu_phys, (long long*)&size, (long long*)&dev_addr);
  char path[512];
  if (n >= 2) {
    if (n == 2) dev_addr = cpu_phys;
    snprintf(path, sizeof path, "/dev/mem");
  } else {
    uint64_t p, s;
    snprintf(path, sizeof path, "/sys/class/u-dma-buf/%s/phys_addr", dma);
    if (read_sysfs_u64(path, &p) != 0) {
      rtaccel_set_open_error("%s: cannot read (is the u-dma-buf module loaded with a buffer named %s?)", path, dma);
      return open_fail(x, RTACCEL_ERR_FILE);
    }
    snprintf(path, sizeof path, "/sys/class/u-dma-buf/%s/size", dma);
    if (read_sysfs_u64(path, &s) != 0) {
      rtaccel_set_open_error("%s: cannot read", path);
      return open_fail(x, RTACCEL_ERR_FILE);
    }
    cpu_phys = dev_addr = p;
    size = s;
    snprintf(path, sizeof path, "/dev/%s", dma);
  }
  x->buf_fd = open(path, O_RDWR | O_SYNC); /* O_SYNC: uncached mapping, no cache maintenance needed */
  if (x->buf_fd < 0) {
    rtaccel_set_open_error("%s: cannot open: %s", path, strerror(errno));
    return open_fail(x, RTACCEL_ERR_FILE);
  }
  void* b = mmap(NULL, size, PROT_READ | PROT_WRITE, MAP_SHARED, x->buf_fd, n >= 2 ? (off_t)cpu_phys : 0);
  if (b == MAP_FAILED) {
    rtaccel_set_open_error("%s: mmap of %llu bytes: %s", path, size, strerror(errno));
    return open_fail(x, RTACCEL_ERR_DEVICE);
  }
  x->buf = b;
  x->buf_dev = dev_addr;
  x->buf_size = size;
  return rtaccel_attach(&uio_backend, x, dev_addr, size, out);
}
