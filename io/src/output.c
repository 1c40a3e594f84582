/* output.c -- checked output paths, atomic replacement, signal clean-up, child processes,
 * provenance and CSV quoting (output.h). */
#include "io/output.h"

#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <pthread.h>
#include <signal.h>
#include <spawn.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

extern char **environ;

/* ---- provenance ---------------------------------------------------------------------------- */

static char command_line[8192];
static char start_date[32];
static io_provenance_t provenance = {"unknown", "unknown", "unknown", "unknown"};

/* Append arg to buf, in single quotes when it holds anything a shell would interpret. */
static size_t append_quoted(char *buf, size_t n, size_t cap, const char *arg) {
  int plain = *arg != '\0';
  for (const char *p = arg; *p && plain; p++)
    plain = strchr("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789-_./=,:+@%",
                   *p) != NULL;
  if (plain)
    return n + (size_t)snprintf(buf + n, n < cap ? cap - n : 0, "%s", arg);
  n += (size_t)snprintf(buf + n, n < cap ? cap - n : 0, "'");
  for (const char *p = arg; *p; p++)
    n += (size_t)snprintf(buf + n, n < cap ? cap - n : 0, *p == '\'' ? "'\\''" : "%c", *p);
  return n + (size_t)snprintf(buf + n, n < cap ? cap - n : 0, "'");
}

void io_provenance_set(const char *version, const char *commit, int argc, char **argv) {
  size_t n = 0;
  for (int i = 0; i < argc; i++) {
    if (i > 0)
      n += (size_t)snprintf(command_line + n, n < sizeof command_line ? sizeof command_line - n : 0,
                            " ");
    n = append_quoted(command_line, n, sizeof command_line, argv[i]);
  }
  time_t t = time(NULL);
  struct tm tm;
  gmtime_r(&t, &tm);
  strftime(start_date, sizeof start_date, "%Y-%m-%dT%H:%M:%SZ", &tm);
  provenance = (io_provenance_t){version, commit, command_line, start_date};
}

const io_provenance_t *io_provenance(void) {
  return &provenance;
}

static char command_name[128] = "pencil";

void io_command_set(const char *name) {
  snprintf(command_name, sizeof command_name, "%s", name);
}

const char *io_command(void) {
  return command_name;
}

/* ---- checks -------------------------------------------------------------------------------- */

/* The inputs io_protect_input() marked: device, inode and the name they were read by. */
enum { MAX_INPUTS = 16 };
static struct {
  dev_t dev;
  ino_t ino;
  char path[512];
} inputs[MAX_INPUTS];
static int ninputs;
static pthread_mutex_t inputs_lock = PTHREAD_MUTEX_INITIALIZER;

int io_protect_input(const char *path) {
  struct stat st;
  if (!path || stat(path, &st) != 0 || !S_ISREG(st.st_mode))
    return -1;
  pthread_mutex_lock(&inputs_lock);
  int known = 0;
  for (int i = 0; i < ninputs && !known; i++)
    known = inputs[i].dev == st.st_dev && inputs[i].ino == st.st_ino;
  if (!known && ninputs < MAX_INPUTS) {
    inputs[ninputs].dev = st.st_dev;
    inputs[ninputs].ino = st.st_ino;
    snprintf(inputs[ninputs].path, sizeof inputs[ninputs].path, "%s", path);
    ninputs++;
  }
  pthread_mutex_unlock(&inputs_lock);
  return 0;
}

/* The marked input that st is, or NULL. */
static const char *input_of(const struct stat *st, char *name, size_t cap) {
  const char *found = NULL;
  pthread_mutex_lock(&inputs_lock);
  for (int i = 0; i < ninputs && !found; i++)
    if (inputs[i].dev == st->st_dev && inputs[i].ino == st->st_ino)
      found = (snprintf(name, cap, "%s", inputs[i].path), name);
  pthread_mutex_unlock(&inputs_lock);
  return found;
}

int io_output_check(const char *path, char *err, size_t cap) {
  struct stat st;
  if (!path || !*path)
    return snprintf(err, cap, "an output path is empty"), -1;
  if (strlen(path) + 16 >= sizeof((io_atomic_t *)0)->tmp)
    return snprintf(err, cap, "%.64s...: the output path is too long", path), -1;
  if (stat(path, &st) == 0 && !S_ISREG(st.st_mode))
    return snprintf(err, cap, "%s: exists and is not a regular file (%s); not replaced", path,
                    S_ISDIR(st.st_mode) ? "a directory" : "a device, FIFO or socket"),
           -1;
  char in[512];
  if (stat(path, &st) == 0 && input_of(&st, in, sizeof in))
    return snprintf(err, cap, "%s: is the input %s; not replaced", path, in), -1;
  char dir[4096];
  const char *slash = strrchr(path, '/');
  if (!slash)
    strcpy(dir, ".");
  else if (slash == path)
    strcpy(dir, "/");
  else
    snprintf(dir, sizeof dir, "%.*s", (int)(slash - path), path);
  if (stat(dir, &st) != 0 || !S_ISDIR(st.st_mode))
    return snprintf(err, cap, "%s: the directory %s does not exist", path, dir), -1;
  if (access(dir, W_OK | X_OK) != 0)
    return snprintf(err, cap, "%s: the directory %s is not writable: %s", path, dir,
                    strerror(errno)),
           -1;
  return 0;
}

int io_output_not_input(const char *out, const char *in, char *err, size_t cap) {
  struct stat so, si;
  if (out && in && stat(out, &so) == 0 && stat(in, &si) == 0 && so.st_dev == si.st_dev &&
      so.st_ino == si.st_ino)
    return snprintf(err, cap, "%s: is the input %s; not replaced", out, in), -1;
  return 0;
}

/* ---- temporary files and signals ----------------------------------------------------------- */

/* Paths the signal handler removes (files, then the directories they emptied), and the child
 * process it stops first. */
enum { MAX_TEMPS = 64 };
static char temps[MAX_TEMPS][4096];
static volatile sig_atomic_t temp_used[MAX_TEMPS];
static volatile sig_atomic_t child_pid; /* a running child of io_run*, or 0 */

/* 0, or -1 when every slot is taken. */
static int temp_register(const char *tmp) {
  sigset_t all, old; /* the handler never sees a half-copied path */
  sigfillset(&all);
  pthread_sigmask(SIG_BLOCK, &all, &old);
  int held = -1;
  for (int k = 0; k < MAX_TEMPS && held < 0; k++)
    if (!temp_used[k]) {
      memcpy(temps[k], tmp, strlen(tmp) + 1);
      temp_used[k] = 1;
      held = 0;
    }
  pthread_sigmask(SIG_SETMASK, &old, NULL);
  return held;
}

static void temp_unregister(const char *tmp) {
  for (int k = 0; k < MAX_TEMPS; k++)
    if (temp_used[k] && strcmp(temps[k], tmp) == 0)
      temp_used[k] = 0;
}

int io_temp_register(const char *path, char *err, size_t cap) {
  for (int k = 0; k < MAX_TEMPS; k++)
    if (temp_used[k] && strcmp(temps[k], path) == 0)
      return 0; /* held already */
  if (strlen(path) >= sizeof temps[0])
    return snprintf(err, cap, "%.64s...: the path is too long to be removed on a signal", path), -1;
  if (temp_register(path) != 0)
    return snprintf(err, cap,
                    "%s: cannot be removed on a signal: %d temporary paths are held already", path,
                    (int)MAX_TEMPS),
           -1;
  return 0;
}

void io_temp_unregister(const char *path) {
  temp_unregister(path);
}

void io_temp_unregister_under(const char *dir) {
  size_t n = strlen(dir);
  for (int k = 0; k < MAX_TEMPS; k++)
    if (temp_used[k] && strncmp(temps[k], dir, n) == 0 && (temps[k][n] == '/' || !temps[k][n]))
      temp_used[k] = 0;
}

/* The signals the clean-up handles. */
static void cleanup_signals(sigset_t *set) {
  sigemptyset(set);
  sigaddset(set, SIGINT);
  sigaddset(set, SIGTERM);
  sigaddset(set, SIGHUP);
}

/* The thread that installed the clean-up (main()'s), which registers paths and waits for
 * children with the signals blocked around each step. */
static pthread_t main_thread;
static volatile sig_atomic_t main_thread_set;

static void on_signal(int sig) {
  /* A process-directed signal goes to any thread that does not block it: while the main thread
   * holds the signals (a file made and not yet registered, a child spawned and not yet recorded),
   * an OpenMP worker would take it and end the process inside that window. Forwarded, it waits
   * until the main thread lets it in. pthread_kill() is async-signal-safe. */
  if (main_thread_set && !pthread_equal(pthread_self(), main_thread)) {
    pthread_kill(main_thread, sig);
    return;
  }
  if (child_pid > 0)
    kill((pid_t)child_pid, SIGTERM);   /* all three are async-signal-safe */
  for (int pass = 0; pass < 4; pass++) /* nested directories empty one level a pass */
    for (int k = MAX_TEMPS - 1; k >= 0; k--)
      if (temp_used[k] && (unlink(temps[k]) == 0 || rmdir(temps[k]) == 0))
        temp_used[k] = 0;
  signal(sig, SIG_DFL);
  raise(sig);
}

void io_cleanup_on_signals(void) {
  static const int sigs[] = {SIGINT, SIGTERM, SIGHUP};
  main_thread = pthread_self();
  main_thread_set = 1;
  for (size_t k = 0; k < sizeof sigs / sizeof sigs[0]; k++) {
    struct sigaction sa;
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = on_signal;
    cleanup_signals(&sa.sa_mask); /* a second signal waits for the first's clean-up */
    sigaction(sigs[k], &sa, NULL);
  }
}

static int begin(io_atomic_t *a, const char *path, int keep_open, char *err, size_t cap) {
  a->tmp[0] = '\0';
  a->f = NULL;
  if (io_output_check(path, err, cap) != 0)
    return -1;
  snprintf(a->path, sizeof a->path, "%s", path);
  const char *slash = strrchr(path, '/');
  int dirlen = slash ? (int)(slash - path + 1) : 0;
  snprintf(a->tmp, sizeof a->tmp, "%.*s.%s.XXXXXX", dirlen, path, slash ? slash + 1 : path);
  sigset_t all, old; /* no signal between creating the file and registering it */
  sigfillset(&all);
  pthread_sigmask(SIG_BLOCK, &all, &old);
  int fd = mkstemp(a->tmp), held = fd >= 0 ? temp_register(a->tmp) : 0;
  if (held != 0) { /* a signal now would leave it behind: no file rather than a stray one */
    close(fd);
    unlink(a->tmp);
  }
  pthread_sigmask(SIG_SETMASK, &old, NULL);
  if (fd < 0 || held != 0) {
    if (fd < 0)
      snprintf(err, cap, "%s: cannot create a temporary file beside it: %s", path, strerror(errno));
    else
      snprintf(err, cap,
               "%s: cannot write it: %d temporary files are held for the clean-up on signals "
               "already",
               path, (int)MAX_TEMPS);
    a->tmp[0] = '\0';
    return -1;
  }
  mode_t mask = umask(0); /* the permissions a plain fopen() would give */
  umask(mask);
  fchmod(fd, 0666 & ~mask);
  if (keep_open && !(a->f = fdopen(fd, "w"))) {
    snprintf(err, cap, "%s: %s", path, strerror(errno));
    close(fd);
    io_atomic_abort(a);
    return -1;
  }
  if (!keep_open)
    close(fd);
  return 0;
}

int io_atomic_begin(io_atomic_t *a, const char *path, char *err, size_t cap) {
  return begin(a, path, 0, err, cap);
}

int io_atomic_open(io_atomic_t *a, const char *path, char *err, size_t cap) {
  return begin(a, path, 1, err, cap);
}

int io_atomic_commit(io_atomic_t *a, char *err, size_t cap) {
  int failed = 0;
  if (a->f) {
    failed = ferror(a->f) != 0;
    failed |= fclose(a->f) != 0;
    a->f = NULL;
    if (failed)
      snprintf(err, cap, "%s: error writing the file", a->path);
  }
  if (!failed && rename(a->tmp, a->path) != 0) {
    snprintf(err, cap, "%s: cannot replace it: %s", a->path, strerror(errno));
    failed = 1;
  }
  if (failed) {
    io_atomic_abort(a);
    return -1;
  }
  temp_unregister(a->tmp);
  a->tmp[0] = '\0';
  return 0;
}

void io_atomic_abort(io_atomic_t *a) {
  if (a->f) {
    fclose(a->f);
    a->f = NULL;
  }
  if (a->tmp[0]) {
    unlink(a->tmp);
    temp_unregister(a->tmp);
    a->tmp[0] = '\0';
  }
}

/* ---- child processes ----------------------------------------------------------------------- */

/* 0 for a child that exited with status 0; else -1 with how it ended. */
static int exit_status(const char *prog, int status, char *err, size_t cap) {
  if (WIFEXITED(status) && WEXITSTATUS(status) == 0)
    return 0;
  if (WIFEXITED(status))
    snprintf(err, cap, "%s exited with status %d", prog, WEXITSTATUS(status));
  else
    snprintf(err, cap, "%s was killed by signal %d", prog, WTERMSIG(status));
  return -1;
}

/* Run argv (file actions fa, may be NULL; environment envp) and wait for it into *status and *ru.
 * The signal clean-up knows the child from before it can run (the signals are blocked across
 * posix_spawn, the child getting the caller's mask back) until it has exited, and never after it
 * is reaped (waitid() without reaping first), so that it stops this child and no other process.
 * 0; else an errno value, *started telling whether the child ran. */
static int spawn_wait(char *const argv[], char *const envp[], const posix_spawn_file_actions_t *fa,
                      int *status, struct rusage *ru, int *started) {
  *started = 0;
  sigset_t sigs, old;
  cleanup_signals(&sigs);
  posix_spawnattr_t at;
  int rc = posix_spawnattr_init(&at);
  if (rc != 0)
    return rc;
  pthread_sigmask(SIG_BLOCK, &sigs, &old);
  rc = posix_spawnattr_setsigmask(&at, &old);
  if (rc == 0)
    rc = posix_spawnattr_setflags(&at, POSIX_SPAWN_SETSIGMASK);
  pid_t pid = 0;
  if (rc == 0)
    rc = posix_spawn(&pid, argv[0], fa, &at, argv, envp);
  if (rc == 0)
    child_pid = pid;
  pthread_sigmask(SIG_SETMASK, &old, NULL); /* a signal that came meanwhile stops the child */
  posix_spawnattr_destroy(&at);
  if (rc != 0)
    return rc;
  *started = 1;
  siginfo_t si;
  while (waitid(P_PID, pid, &si, WEXITED | WNOWAIT) < 0)
    if (errno != EINTR) {
      child_pid = 0;
      return errno;
    }
  child_pid = 0;
  while (wait4(pid, status, 0, ru) < 0)
    if (errno != EINTR)
      return errno;
  return 0;
}

int io_run(char *const argv[], char *err, size_t cap) {
  int status = 0, started;
  struct rusage ru;
  fflush(NULL); /* what this process wrote comes before the child's output on the same streams */
  int rc = spawn_wait(argv, environ, NULL, &status, &ru, &started);
  if (rc != 0)
    return snprintf(err, cap, "%s: %s%s", argv[0], started ? "" : "cannot start: ", strerror(rc)),
           -1;
  return exit_status(argv[0], status, err, cap);
}

int io_run_logged(char *const argv[], char *const envp[], const char *log, double *cpu_s, char *err,
                  size_t cap) {
  posix_spawn_file_actions_t fa;
  int status = 0, started = 0, rc = posix_spawn_file_actions_init(&fa);
  if (rc != 0)
    return snprintf(err, cap, "%s: cannot start (log %s): %s", argv[0], log, strerror(rc)), -1;
  rc = posix_spawn_file_actions_addopen(&fa, 0, "/dev/null", O_RDONLY, 0);
  if (rc == 0)
    rc = posix_spawn_file_actions_addopen(&fa, 1, log, O_WRONLY | O_CREAT | O_TRUNC, 0644);
  if (rc == 0)
    rc = posix_spawn_file_actions_adddup2(&fa, 1, 2);
  struct rusage ru;
  if (rc == 0)
    rc = spawn_wait(argv, envp ? envp : environ, &fa, &status, &ru, &started);
  posix_spawn_file_actions_destroy(&fa);
  if (rc != 0 && !started)
    return snprintf(err, cap, "%s: cannot start (log %s): %s", argv[0], log, strerror(rc)), -1;
  if (rc != 0)
    return snprintf(err, cap, "%s: %s", argv[0], strerror(rc)), -1;
  if (cpu_s)
    *cpu_s = (double)ru.ru_utime.tv_sec + 1e-6 * (double)ru.ru_utime.tv_usec +
             (double)ru.ru_stime.tv_sec + 1e-6 * (double)ru.ru_stime.tv_usec;
  return exit_status(argv[0], status, err, cap);
}

/* ---- CSV ----------------------------------------------------------------------------------- */

const char *io_shortest(double v, char buf[IO_SHORTEST_MAX]) {
  /* at least the integer digits below 1e17, so that 200 is not written 2e+02 */
  int x = isfinite(v) && v != 0.0 ? (int)floor(log10(fabs(v))) : 0;
  for (int digits = x >= 0 && x < 17 ? x + 1 : 1; digits <= 17; digits++) {
    snprintf(buf, IO_SHORTEST_MAX, "%.*g", digits, v);
    if (strtod(buf, NULL) == v)
      break; /* 17 digits read back as every double; NaN stops there too */
  }
  return buf;
}

/* s on one comment line: control characters escaped. */
static void comment_text(FILE *f, const char *s) {
  for (const unsigned char *p = (const unsigned char *)s; *p; p++) {
    if (*p == '\n')
      fputs("\\n", f);
    else if (*p == '\t')
      fputs("\\t", f);
    else if (*p < 0x20 || *p == 0x7F)
      fprintf(f, "\\x%02X", *p);
    else
      fputc(*p, f);
  }
}

int io_csv_open(io_atomic_t *a, const char *path, char *err, size_t cap) {
  if (io_atomic_open(a, path, err, cap) != 0)
    return -1;
  const io_provenance_t *p = io_provenance();
  const char *const keys[4] = {"version", "commit", "date", "command_line"};
  const char *const values[4] = {p->version, p->commit, p->date, p->command_line};
  for (int k = 0; k < 4; k++) {
    fprintf(a->f, "# %s: ", keys[k]);
    comment_text(a->f, values[k]);
    fputc('\n', a->f);
  }
  return 0;
}

void io_csv_field(FILE *f, const char *s) {
  size_t n = strlen(s);
  int quote = n > 0 && (s[0] == ' ' || s[n - 1] == ' ');
  for (const char *p = s; *p && !quote; p++)
    quote = *p == ',' || *p == '"' || *p == '\n' || *p == '\r';
  if (!quote) {
    fputs(s, f);
    return;
  }
  fputc('"', f);
  for (const char *p = s; *p; p++) {
    if (*p == '"')
      fputc('"', f);
    fputc(*p, f);
  }
  fputc('"', f);
}

/* ---- memory -------------------------------------------------------------------------------- */

size_t io_memory_available(void) {
  FILE *f = fopen("/proc/meminfo", "r");
  char line[256];
  unsigned long long kb = 0;
  while (f && fgets(line, sizeof line, f))
    if (sscanf(line, "MemAvailable: %llu kB", &kb) == 1)
      break;
  if (f)
    fclose(f);
  if (kb > 0)
    return kb > SIZE_MAX / 1024 ? SIZE_MAX : (size_t)kb * 1024;
  long pages = sysconf(_SC_AVPHYS_PAGES), page = sysconf(_SC_PAGESIZE);
  return pages > 0 && page > 0 ? (size_t)pages * (size_t)page : 0;
}

int io_parse_size(const char *text, size_t *bytes) {
  char *end = NULL;
  const char *d = text; /* digits with an optional point, as the command's numbers: no '+', no
                           spaces, no hexadecimal or exponent */
  while (*d >= '0' && *d <= '9')
    d++;
  if (d == text || (*d == '.' && !(d[1] >= '0' && d[1] <= '9')))
    return 0;
  if (*d == '.')
    for (d++; *d >= '0' && *d <= '9'; d++)
      ;
  double v = strtod(text, &end);
  if (end != d) /* strtod read more: 0x10, 1e9 */
    return 0;
  double unit = 1.0;
  if (*end && end[1] == '\0') {
    const char *units = "KMGT";
    const char *u = strchr(units, *end == 'k' ? 'K' : *end);
    if (!u || !*u)
      return 0;
    for (const char *p = units; p <= u; p++)
      unit *= 1024.0;
    end++;
  }
  if (*end != '\0' || !(v * unit >= 1.0) || v * unit >= (double)SIZE_MAX)
    return 0;
  *bytes = (size_t)(v * unit);
  return 1;
}

void io_format_size(size_t bytes, char *buf, size_t cap) {
  static const char *const units[] = {"bytes", "KB", "MB", "GB", "TB"};
  double v = (double)bytes;
  int k = 0;
  while (v >= 1024.0 && k < 4)
    v /= 1024.0, k++;
  snprintf(buf, cap, k == 0 ? "%.0f %s" : "%.1f %s", v, units[k]);
}

char *io_read_file(const char *path, size_t *len) {
  FILE *f = fopen(path, "rb");
  if (!f)
    return NULL;
  size_t cap = 1 << 16, n = 0, got;
  char *buf = malloc(cap);
  while (buf && (got = fread(buf + n, 1, cap - 1 - n, f)) > 0) {
    n += got;
    if (n + 1 < cap)
      continue;
    char *bigger = realloc(buf, cap *= 2);
    if (!bigger)
      free(buf);
    buf = bigger;
  }
  if (buf && ferror(f)) {
    free(buf);
    buf = NULL;
  }
  fclose(f);
  if (buf)
    buf[n] = '\0';
  *len = buf ? n : 0;
  return buf;
}

int io_make_dirs(const char *d) {
  char buf[4096];
  size_t n = strlen(d);
  if (n == 0 || n >= sizeof buf)
    return -1;
  memcpy(buf, d, n + 1);
  for (size_t i = 1; i <= n; i++)
    if (buf[i] == '/' || buf[i] == '\0') {
      char c = buf[i];
      buf[i] = '\0';
      if (mkdir(buf, 0777) != 0 && errno != EEXIST) {
        fprintf(stderr, "%s: cannot create directory %s: %s\n", io_command(), buf, strerror(errno));
        return -1;
      }
      buf[i] = c;
    }
  struct stat st;
  if (stat(d, &st) != 0 || !S_ISDIR(st.st_mode)) {
    fprintf(stderr, "%s: %s exists and is not a directory\n", io_command(), d);
    return -1;
  }
  if (access(d, W_OK | X_OK) != 0) { /* found now, not at the first file after the work */
    fprintf(stderr, "%s: cannot write in directory %s: %s\n", io_command(), d, strerror(errno));
    return -1;
  }
  return 0;
}
