/* The register names the driver uses, all from the generated rtaccel_regs.h
 * (src/main/scala/rtaccel/system/RegisterMap.scala is the one source; never
 * write an offset by hand). This file only includes it and checks at compile
 * time that every register the driver needs is there. */
#ifndef RTACCEL_DRIVER_REGS_H
#define RTACCEL_DRIVER_REGS_H
#include "rtaccel_regs.h"

#if !defined(RTACCEL_ID_OFFSET) || !defined(RTACCEL_CTRL_OFFSET) || !defined(RTACCEL_STATUS_OFFSET) || \
    !defined(RTACCEL_SCENE_BASE_OFFSET) || !defined(RTACCEL_RAY_BASE_OFFSET) || !defined(RTACCEL_HIT_BASE_OFFSET) || \
    !defined(RTACCEL_IRQ_STATUS_OFFSET) || !defined(RTACCEL_CYCLES_LO_OFFSET) || !defined(RTACCEL_SCENE_ERROR_CODE_OFFSET)
#error "rtaccel_regs.h lacks registers of the contract (regenerate it: make regmap)"
#endif
#endif
