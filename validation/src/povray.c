/* povray.c -- POV-Ray 3.7 as a peer of the exact renderer (validation/povray.h; issue 26): the
 * program found, its private directory, the export, the render and its statistics read back. */
#include "validation/povray.h"

#include <dirent.h>
#include <errno.h>
#include <math.h>
#include <pthread.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "io/output.h"
#include "io/pov.h"

/* The executable `name` in a directory of PATH, as an absolute path; 0 when none. */
static int find_on_path(const char *name, char *out, size_t cap) {
  const char *path = getenv("PATH");
  for (const char *p = path ? path : ""; *p;) {
    const char *e = strchr(p, ':');
    size_t n = e ? (size_t)(e - p) : strlen(p);
    struct stat st;
    if (n > 0 && p[0] == '/' && (size_t)snprintf(out, cap, "%.*s/%s", (int)n, p, name) < cap &&
        stat(out, &st) == 0 && S_ISREG(st.st_mode) && access(out, X_OK) == 0)
      return 1;
    p += n + (e != NULL);
  }
  out[0] = '\0';
  return 0;
}

/* DIR/rel registered for the signal clean-up (an interrupted run leaves no private directory;
 * io_cleanup_on_signals also stops POV-Ray); -1 (err set) when it cannot be. */
static int hold(const char *dir, const char *rel, char *err, size_t cap) {
  char path[4200];
  snprintf(path, sizeof path, "%s/%s", dir, rel);
  return io_temp_register(path, err, cap);
}

/* An empty file at DIR/rel, registered for the signal clean-up. */
static int touch(const char *dir, const char *rel, char *err, size_t cap) {
  char path[4200];
  snprintf(path, sizeof path, "%s/%s", dir, rel);
  if (hold(dir, rel, err, cap) != 0)
    return -1;
  FILE *f = fopen(path, "w");
  if (f && fclose(f) == 0)
    return 0;
  snprintf(err, cap, "%s: cannot write POV-Ray's empty configuration: %s", path, strerror(errno));
  return -1;
}

int val_povray_open(val_povray_t *p, char *err, size_t cap) {
  memset(p, 0, sizeof *p);
  if (!find_on_path("povray", p->exe, sizeof p->exe)) {
    snprintf(err, cap,
             "povray (POV-Ray 3.7) is not installed (not on PATH; scripts/deps "
             "installs Debian's package povray)");
    return 1;
  }
  const char *tmp = getenv("TMPDIR");
  snprintf(p->dir, sizeof p->dir, "%s/pencil-povray-XXXXXX", tmp && tmp[0] ? tmp : "/tmp");
  if (strchr(p->dir, '"')) { /* POV-Ray's +I"..." cannot quote one */
    snprintf(err, cap, "%s: a directory name with '\"' cannot be given to POV-Ray (set TMPDIR)",
             p->dir);
    p->dir[0] = '\0';
    return -1;
  }
  sigset_t all, old; /* no signal between making the directory and registering it */
  sigfillset(&all);
  pthread_sigmask(SIG_BLOCK, &all, &old);
  int made = mkdtemp(p->dir) != NULL, held = made && io_temp_register(p->dir, err, cap) == 0;
  if (made && !held)
    rmdir(p->dir);
  pthread_sigmask(SIG_SETMASK, &old, NULL);
  if (!made)
    snprintf(err, cap, "%s: cannot make POV-Ray's private directory: %s", p->dir, strerror(errno));
  if (!held) {
    p->dir[0] = '\0';
    return -1;
  }
  char conf[4200];
  snprintf(conf, sizeof conf, "%s/.povray/3.7", p->dir);
  if (hold(p->dir, ".povray", err, cap) != 0 || hold(p->dir, ".povray/3.7", err, cap) != 0) {
    val_povray_close(p);
    return -1;
  }
  if (io_make_dirs(conf) != 0) {
    snprintf(err, cap, "%s: cannot make POV-Ray's configuration directory", conf);
    val_povray_close(p);
    return -1;
  }
  if (touch(p->dir, ".povray/3.7/povray.conf", err, cap) != 0 ||
      touch(p->dir, "povray.ini", err, cap) != 0) {
    val_povray_close(p);
    return -1;
  }
  return 0;
}

void val_povray_close(val_povray_t *p) {
  if (!p->dir[0])
    return;
  char path[4400];
  DIR *d = opendir(p->dir); /* the .pov and .log files, povray.ini */
  for (struct dirent *e; d && (e = readdir(d));)
    if (e->d_name[0] != '.') {
      snprintf(path, sizeof path, "%s/%s", p->dir, e->d_name);
      remove(path);
    }
  if (d)
    closedir(d);
  static const char *const conf[] = {".povray/3.7/povray.conf", ".povray/3.7", ".povray", ""};
  for (int k = 0; k < 4; k++) {
    snprintf(path, sizeof path, "%s/%s", p->dir, conf[k]);
    remove(path);
  }
  io_temp_unregister_under(p->dir); /* also what was registered and never made */
  p->dir[0] = '\0';
}

int val_povray_export(val_povray_t *p, const rt_scene_t *s, int spp, const char *source, char *err,
                      size_t cap) {
  char path[4200];
  snprintf(path, sizeof path, "%s/scene-%d.pov", p->dir, spp);
  if (io_temp_register(path, err, cap) != 0)
    return -1;
  io_pov_options_t o = IO_POV_OPTIONS_DEFAULT;
  o.spp = spp;
  o.source = source;
  return io_pov_export(path, s, &o, NULL, 0, err, cap);
}

/* The unsigned number after `key` at the start of a line of log; 0 when there is none. */
static int count_after(const char *log, const char *key, uint64_t *v) {
  size_t n = strlen(key);
  for (const char *p = log; p; p = strchr(p, '\n')) {
    p += *p == '\n';
    unsigned long long x;
    if (strncmp(p, key, n) == 0 && sscanf(p + n, " %llu", &x) == 1) {
      *v = x;
      return 1;
    }
  }
  return 0;
}

int val_povray_parse(const char *log, val_povray_run_t *out, char *version, size_t vcap, char *err,
                     size_t cap) {
  const char *t = strstr(log, "Trace Time:");
  const char *w = t ? strstr(t, " with ") : NULL;
  if (!w || sscanf(w, " with %lf CPU-seconds total", &out->trace_s) != 1 || !(out->trace_s >= 0.0))
    return snprintf(err, cap, "no \"Trace Time: ... CPU-seconds total\" line"), -1;
  if (!count_after(log, "Rays:", &out->rays))
    return snprintf(err, cap, "no \"Rays:\" line"), -1;
  if (!count_after(log, "Shadow Ray Tests:", &out->shadow_tests))
    out->shadow_tests = 0; /* POV-Ray leaves the line out when it traced no shadow ray */
  const char *v = strstr(log, "Ray Tracer Version ");
  char word[64] = "";
  if (version && vcap > 0)
    snprintf(version, vcap, "%s",
             v && sscanf(v + strlen("Ray Tracer Version "), "%63s", word) == 1 ? word : "");
  return 0;
}

int val_povray_peer_run(void *ctx, int spp, double *seconds, uint64_t *rays) {
  val_povray_peer_t *c = ctx;
  char err[1024];
  if (val_povray_render(c->pv, c->s, spp, c->threads, &c->last, err, sizeof err) != 0)
    return fprintf(stderr, "%s: --peer povray: %s\n", c->who, err), -1;
  if (c->n < 101)
    c->process[c->n++] = c->last.process_s;
  *seconds = c->last.trace_s;
  *rays = c->last.rays + c->last.shadow_tests;
  return 0;
}

/* The last lines of file `path` (at most cap - 1 characters, lines joined by " | ", control
 * characters as spaces), or "(none)". */
static void log_tail(const char *path, char *out, size_t cap) {
  size_t len = 0;
  char *text = io_read_file(path, &len);
  snprintf(out, cap, "(none)");
  if (!text)
    return;
  while (len > 0 && (text[len - 1] == '\n' || text[len - 1] == '\r' || text[len - 1] == ' '))
    len--;
  size_t start = len > cap - 1 ? len - (cap - 1) : 0, o = 0;
  for (size_t i = start; i < len && o + 3 < cap; i++) {
    unsigned char ch = (unsigned char)text[i];
    if (ch == '\n') {
      memcpy(out + o, " | ", 3);
      o += 3;
    } else
      out[o++] = ch < 0x20 || ch == 0x7f ? ' ' : (char)ch;
  }
  out[o] = '\0';
  if (o == 0)
    snprintf(out, cap, "(none)");
  free(text);
}

int val_povray_render(val_povray_t *p, const rt_scene_t *s, int spp, int threads,
                      val_povray_run_t *out, char *err, size_t cap) {
  int side = (int)lrint(sqrt((double)spp));
  char in[4200], log[4200], w[32], h[32], wt[32], home[4200], ini[4200];
  /* quoted: POV-Ray splits an unquoted switch at a space (open() refused a '"' in dir) */
  snprintf(in, sizeof in, "+I\"%s/scene-%d.pov\"", p->dir, spp);
  snprintf(log, sizeof log, "%s/scene-%d.log", p->dir, spp);
  if (io_temp_register(log, err, cap) != 0)
    return -1;
  snprintf(w, sizeof w, "+W%d", side * s->camera.width);
  snprintf(h, sizeof h, "+H%d", side * s->camera.height);
  snprintf(wt, sizeof wt, "+WT%d", threads);
  snprintf(home, sizeof home, "HOME=%s", p->dir);
  snprintf(ini, sizeof ini, "POVINI=%s/povray.ini", p->dir);
  char *argv[] = {p->exe, in, w, h, "-A", wt, "-F", "-D", "-V", NULL};
  char *envp[] = {home, ini, NULL};
  char why[512];
  if (io_run_logged(argv, envp, log, &out->process_s, why, sizeof why) != 0) {
    char tail[400]; /* the log goes with the private directory: its last lines into the message */
    log_tail(log, tail, sizeof tail);
    return snprintf(err, cap, "%s; the end of its output: %s", why, tail), -1;
  }
  size_t len;
  char *text = io_read_file(log, &len);
  if (!text)
    return snprintf(err, cap, "%s: cannot read POV-Ray's output", log), -1;
  int rc = val_povray_parse(text, out, p->version, sizeof p->version, why, sizeof why);
  free(text);
  if (rc != 0)
    snprintf(err, cap, "%s: POV-Ray's statistics: %s", log, why);
  return rc;
}
