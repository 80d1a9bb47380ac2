/* In-process link tests: an emulated board (board_emu/emu_board.h) plugged in as a umockdev USB
 * device (board_emu/usb_device.h) that libusb in this very process can open. The process must
 * run with umockdev's preload library loaded (tests/link_test.sh sets LD_PRELOAD); bring the
 * fixture up before libusb_init and take it down after libusb_exit. */
#ifndef C5_USB_FIXTURE_H
#define C5_USB_FIXTURE_H

#include "emu_board.h"
#include "usb_device.h"

typedef struct {
    c5_emu *board;
    c5_usb_device *usb;
    char msg[512]; /* why c5_link_fixture_up failed */
} c5_link_fixture;

/* A board in its reset state with this serial (NULL: the default) on the emulated bus.
 * 0, or -1 with the reason in f->msg (no preload, umockdev failure). */
int c5_link_fixture_up(c5_link_fixture *f, const char *serial);
/* Unplugs and frees; a fixture that is not up (zeroed, or failed) is fine. */
void c5_link_fixture_down(c5_link_fixture *f);

#endif
