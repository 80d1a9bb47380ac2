/* The emulated board as a USB device (docs/host-protocol.md, transport): a umockdev testbed
 * holds a fake sysfs entry and /dev/bus/usb node for VID:PID 1209:0001, and an ioctl handler
 * answers libusb's usbfs requests (claim, control, bulk URBs) from the board core
 * (emu_board.h). Any unmodified libusb program sees the board, provided umockdev's preload
 * library (libumockdev-preload.so.0) is loaded into it and $UMOCKDEV_DIR (set here) reaches
 * it: board_emu/cube5_board.c runs a program that way, tests/link/usb_fixture.c does it in
 * process. See board_emu/README.md and ../shared/notes/usb-emulation.md.
 *
 * All devices of one process share one testbed (umockdev follows one $UMOCKDEV_DIR); each gets
 * its own device number on bus 1. The testbed goes when its last device is freed. */
#ifndef C5_USB_DEVICE_H
#define C5_USB_DEVICE_H

#include <stddef.h>

#include "emu_board.h"

typedef struct c5_usb_device c5_usb_device;

/* Plugs `board` in as a USB device (the board must outlive the device). Call it before the
 * libusb context that should see the device is created (libusb_init). NULL on failure, with a
 * message of at most `cap` bytes in msg. */
c5_usb_device *c5_usb_device_new(c5_emu *board, char *msg, size_t cap);
/* Unplugs and frees the device; pending URBs are dropped. NULL is allowed. */
void c5_usb_device_free(c5_usb_device *d);

/* The device's node as libusb names it ("/dev/bus/usb/001/002"), its bus and address. */
const char *c5_usb_device_node(const c5_usb_device *d);
int c5_usb_device_busnum(const c5_usb_device *d);
int c5_usb_device_devnum(const c5_usb_device *d);

#endif
