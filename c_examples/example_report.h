/*
 * example_report.h: how the C examples print a failed ccss call: the
 * status, its message and, when the call filled one, the error detail
 * (which face, vertex or edge, and why). Include after ccss.h and stdio.h.
 */
#ifndef CCSS_EXAMPLE_REPORT_H
#define CCSS_EXAMPLE_REPORT_H

#include <stdio.h>

/* Prints what failed and returns 1 (an example's exit code). */
static int report(const char *what, ccss_status st, const ccss_error_detail *d)
{
    char msg[CCSS_ERROR_DETAIL_MESSAGE_CAPACITY];
    fprintf(stderr, "%s failed: %s (status %d)\n", what, ccss_status_message((int)st), (int)st);
    if (d != NULL) {
        ccss_error_detail_format(d, msg, sizeof msg);
        fprintf(stderr, "  detail: %s\n", msg);
    }
    return 1;
}

#endif
