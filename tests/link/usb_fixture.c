/* In-process emulated board on the umockdev bus (usb_fixture.h). */
#include "usb_fixture.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/prctl.h>

int c5_link_fixture_up(c5_link_fixture *f, const char *serial)
{
    memset(f, 0, sizeof *f);
    /* Without the preload libusb would look at the real (empty) /dev/bus/usb and the tests
     * would only time out: say why instead. */
    const char *pre = getenv("LD_PRELOAD");
    if (!pre || !strstr(pre, "umockdev")) {
        snprintf(f->msg, sizeof f->msg,
                 "umockdev's preload is not loaded: run with LD_PRELOAD=libumockdev-preload.so.0 "
                 "(tests/link_test.sh does)");
        return -1;
    }
    prctl(PR_SET_TIMERSLACK, 1UL); /* the preload sleeps after every emulated ioctl */
    f->board = c5_emu_new(serial);
    if (!f->board) {
        snprintf(f->msg, sizeof f->msg, "c5_emu_new failed");
        return -1;
    }
    f->usb = c5_usb_device_new(f->board, f->msg, sizeof f->msg);
    if (!f->usb) {
        c5_emu_free(f->board);
        f->board = NULL;
        return -1;
    }
    return 0;
}

void c5_link_fixture_down(c5_link_fixture *f)
{
    c5_usb_device_free(f->usb);
    if (f->board)
        c5_emu_free(f->board);
    f->usb = NULL;
    f->board = NULL;
}
