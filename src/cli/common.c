/* src/cli/common.c - error reporting, exit codes, option parsing and the progress bar. */
#include <errno.h>
#include <math.h>
#include <signal.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "cli.h"
#include "core/internal.h"
#include "hovox/colour.h"
#include "hovox/mesh.h"
#include "hovox/threemf.h"

int cli_exit_code(hv_status s)
{
    switch (s) {
    case HV_OK: return EXIT_OK;
    case HV_ERR_INVALID:
    case HV_ERR_BAD_INPUT:
    case HV_ERR_NOT_FOUND:
    case HV_ERR_UNSUPPORTED: return EXIT_BAD_INPUT;
    case HV_ERR_IO: return EXIT_IO;
    case HV_ERR_NOMEM:
    case HV_ERR_LIMIT: return EXIT_RESOURCE;
    case HV_ERR_CANCELLED: return EXIT_INTERRUPTED;
    case HV_ERR_INTERNAL: return EXIT_INTERNAL;
    }
    return EXIT_INTERNAL;
}

/* ---- signals and progress -------------------------------------------------------------- */

static volatile sig_atomic_t g_interrupted;
static double g_deadline; /* monotonic seconds; 0: none */

static void on_signal(int sig)
{
    g_interrupted = sig;
}

static double now_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* The library's cancel check: Ctrl-C, SIGTERM or the time limit. */
static int should_stop(void *user)
{
    (void)user;
    return g_interrupted != 0 || cli_out_of_time();
}

void cli_install_signals(void)
{
    struct sigaction sa;
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = on_signal;
    sigemptyset(&sa.sa_mask);
    sigaction(SIGINT, &sa, NULL);
    sigaction(SIGTERM, &sa, NULL);
    hv_set_cancel_check(should_stop, NULL);
}

int cli_interrupted(void) { return g_interrupted != 0; }

void cli_set_time_limit(double seconds) { g_deadline = seconds > 0 ? now_seconds() + seconds : 0; }

int cli_out_of_time(void) { return g_deadline > 0 && now_seconds() > g_deadline; }

void cli_progress_init(cli_progress *p, int quiet)
{
    memset(p, 0, sizeof *p);
    p->enabled = !quiet && isatty(STDERR_FILENO);
}

int cli_progress_fn(void *user, const char *stage, double fraction)
{
    cli_progress *p = user;
    if (g_interrupted) return 1;
    if (!p || !p->enabled) return 0;
    double t = now_seconds();
    int new_stage = strncmp(p->stage, stage, sizeof p->stage - 1) != 0;
    if (!new_stage && t - p->last_draw < 0.1 && fraction < 1.0) return 0;
    if (new_stage && p->drawn) fputc('\n', stderr);
    snprintf(p->stage, sizeof p->stage, "%s", stage);
    p->last_draw = t;
    int width = 40, fill = (int)(fraction * width + 0.5);
    char bar[64];
    for (int i = 0; i < width; ++i) bar[i] = i < fill ? '#' : '.';
    bar[width] = '\0';
    fprintf(stderr, "\r%-14s [%s] %3d%%", stage, bar, (int)(fraction * 100 + 0.5));
    fflush(stderr);
    p->drawn = 1;
    return 0;
}

void cli_progress_done(cli_progress *p)
{
    if (p->enabled && p->drawn) fputc('\n', stderr);
    p->drawn = 0;
    p->stage[0] = '\0';
}

/* An assembly painted by body (issue 29 item 2): which bodies took colour, which kept their
 * materials (hv_colour_mesh_bodies, the rule painting followed; `layers MESH`, `voxelize
 * --colour-depth`). Nothing when all took colour. */
void cli_describe_bodies(const hv_mesh *mesh, int asked, hv_buf *said)
{
    size_t nb = hv_mesh_body_count(mesh);
    uint8_t *paint = malloc(nb);
    if (!paint) return;
    hv_colour_body_rule rule = {asked, NULL, NULL};
    size_t np = hv_colour_mesh_bodies(mesh, &rule, paint);
    for (int pass = 0; np < nb && pass < 2; ++pass) {
        hv_buf_printf(said, pass ? "; in their materials: " : "bodies      painted: ");
        for (size_t i = 0, k = 0; i < nb; ++i) {
            if (paint[i] != !pass) continue;
            const hv_mesh_body *b = hv_mesh_body_at(mesh, i);
            hv_buf_printf(said, "%s%s", k++ ? ", " : "", b->name);
            if (pass) hv_buf_printf(said, " (%s)", hv_mesh_material_at(mesh, (size_t)b->material)->name);
        }
    }
    if (np < nb) hv_buf_printf(said, "\n");
    free(paint);
}
