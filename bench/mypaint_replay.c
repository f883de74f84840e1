/* bench/mypaint_replay: replays a MyPaint stroke-player event file (`t x y
 * pressure` lines, e.g. scenes/recordings/painting30sec-excerpt.dat) with
 * libmypaint's default brush onto a fixed tiled surface, as libmypaint's own
 * stroke player does (each event one mypaint_brush_stroke_to with the time
 * since the one before, inside begin/end_atomic), and prints the wall time
 * of the replay, best of N runs. The bristle side of the comparison is
 * `bristle render --trajectory` on the same file (docs/PERFORMANCE.md,
 * "Memory, and against libmypaint").
 *
 *   mypaint_replay EVENTS.dat [RUNS]   (default 5 runs)
 */
#include <mypaint-brush.h>
#include <mypaint-fixed-tiled-surface.h>

#include <stdio.h>
#include <stdlib.h>
#include <time.h>

typedef struct {
  double t, x, y, pressure;
} Event;

static double now_s(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return ts.tv_sec + ts.tv_nsec * 1e-9;
}

int main(int argc, char** argv) {
  if (argc < 2) {
    fprintf(stderr, "usage: mypaint_replay EVENTS.dat [RUNS]\n");
    return 64;
  }
  const int runs = argc > 2 ? atoi(argv[2]) : 5;
  FILE* f = fopen(argv[1], "r");
  if (!f) {
    perror(argv[1]);
    return 66;
  }
  size_t n = 0, cap = 1024;
  Event* ev = malloc(cap * sizeof *ev);
  double max_x = 0, max_y = 0;
  while (fscanf(f, "%lf %lf %lf %lf", &ev[n].t, &ev[n].x, &ev[n].y, &ev[n].pressure) == 4) {
    if (ev[n].x > max_x) max_x = ev[n].x;
    if (ev[n].y > max_y) max_y = ev[n].y;
    if (++n == cap) ev = realloc(ev, (cap *= 2) * sizeof *ev);
  }
  fclose(f);
  if (n < 2) {
    fprintf(stderr, "%s: fewer than 2 events\n", argv[1]);
    return 65;
  }
  double best = 1e300;
  for (int r = 0; r < runs; ++r) {
    MyPaintFixedTiledSurface* surface =
        mypaint_fixed_tiled_surface_new((int)max_x + 64, (int)max_y + 64);
    MyPaintBrush* brush = mypaint_brush_new();
    mypaint_brush_from_defaults(brush);
    mypaint_brush_set_base_value(brush, MYPAINT_BRUSH_SETTING_COLOR_V, 0.0f);
    const double t0 = now_s();
    double last = 0;
    for (size_t k = 0; k < n; ++k) {
      mypaint_surface_begin_atomic((MyPaintSurface*)surface);
      mypaint_brush_stroke_to(brush, (MyPaintSurface*)surface, (float)ev[k].x, (float)ev[k].y,
                              (float)ev[k].pressure, 0.0f, 0.0f, ev[k].t - last);
      mypaint_surface_end_atomic((MyPaintSurface*)surface, NULL);
      last = ev[k].t;
    }
    const double dt = now_s() - t0;
    if (dt < best) best = dt;
    mypaint_brush_unref(brush);
    mypaint_surface_unref((MyPaintSurface*)surface);
  }
  printf("%s: %zu events, %.3f s of recording; libmypaint default brush: best of %d runs %.6f s\n",
         argv[1], n, ev[n - 1].t, runs, best);
  free(ev);
  return 0;
}
