/* output.h -- how the pencil command writes files: output paths checked before long work,
 * files replaced atomically (a temporary file beside the target, renamed over it when
 * complete, removed on failure and on SIGINT, SIGTERM or SIGHUP), child processes started with
 * an argument vector (posix_spawn, never a shell), and the provenance every output records.
 *
 * Functions return 0 on success, or -1 with a one-line reason naming the file in err[cap].
 * The provenance and the signal clean-up are process-wide: set them once from main(); the rest
 * is thread-safe for distinct paths. */
#ifndef IO_OUTPUT_H
#define IO_OUTPUT_H

#include <stddef.h>
#include <stdio.h>

/** Where an output came from. */
typedef struct {
  const char *version;      /**< the project's version, "0.1.0" */
  const char *commit;       /**< git describe of the build, "ccfbde6" or "ccfbde6-dirty" */
  const char *command_line; /**< the command line, shell-quoted where needed */
  const char *date;         /**< when the command started, ISO 8601 UTC */
} io_provenance_t;

/** Record the provenance of this process's outputs (argv as main() got it; copied). */
void io_provenance_set(const char *version, const char *commit, int argc, char **argv);
/** The provenance set by io_provenance_set(), or "unknown" fields when it was not called. */
const io_provenance_t *io_provenance(void);

/** Name the command for messages ("pencil sweep", "pencil bench star"; copied): errors of io/ and
 *  of the drivers shared by several commands start with it, as the commands' own do. Set once
 *  from main(); "pencil" until then. */
void io_command_set(const char *name);
/** The name io_command_set() gave, or "pencil". */
const char *io_command(void);

/** Create directory d and its missing parents (as mkdir -p), and check that files can be made in
 *  it; 0, or -1 with the reason on stderr. */
int io_make_dirs(const char *d);

/** Check that `path` can be written as a regular file: it is not empty, it is not an existing
 *  directory, device, FIFO or socket, and its directory exists and is writable. */
int io_output_check(const char *path, char *err, size_t cap);

/** -1 with the reason in err when `out` is the same file as the input `in` (which would be
 *  replaced: MAP.json beside MAP.exr for a scene called MAP.json), else 0. */
int io_output_not_input(const char *out, const char *in, char *err, size_t cap);

/** Mark the existing file `path` as an input of this process (io_scene_load() marks every scene
 *  it reads): io_output_check(), and so every file written through io_atomic_begin(), then
 *  refuses to replace it, whatever name the output reaches it by (a sweep's --out directory
 *  holding its scene as sweep.json). Up to 16 inputs are kept; 0, or -1 when it is not a file
 *  (nothing marked). Thread-safe. */
int io_protect_input(const char *path);

/** A file being written: the temporary file beside the target. */
typedef struct {
  char path[4096]; /**< the target */
  char tmp[4096];  /**< the temporary file ("" when none) */
  FILE *f;         /**< open on tmp for io_atomic_open(); NULL for io_atomic_begin() */
} io_atomic_t;

/** Create the temporary file for `path` (checked with io_output_check()) and register it for
 *  removal on a signal; the caller writes it by name (a->tmp). */
int io_atomic_begin(io_atomic_t *a, const char *path, char *err, size_t cap);
/** io_atomic_begin() with the temporary file open for writing as a->f. */
int io_atomic_open(io_atomic_t *a, const char *path, char *err, size_t cap);
/** Close a->f (when open) and rename the temporary file over the target: the file appears
 *  whole or not at all. On failure the temporary file is removed. */
int io_atomic_commit(io_atomic_t *a, char *err, size_t cap);
/** Remove the temporary file (after a failed write); safe to call twice. */
void io_atomic_abort(io_atomic_t *a);

/** Remove registered temporary files when SIGINT, SIGTERM or SIGHUP arrives, then die of the
 *  signal as before; a child process that io_run() or io_run_logged() is waiting for is sent
 *  SIGTERM first. Install once, from main(), in the thread that registers paths and runs
 *  children: a signal that another thread (an OpenMP worker) takes is passed on to it. */
void io_cleanup_on_signals(void);

/** Register a temporary file or directory of the caller's for that clean-up, and unregister it
 *  once it is removed or kept. Files go first, then the directories they leave empty (nested up
 *  to four deep); a directory with unregistered contents stays. 64 paths at most are held, the
 *  atomic writes' temporary files among them: -1 (err says why) when they are all taken or the
 *  path is 4096 bytes or longer, and the caller should not make the path; 0 when it is held
 *  (already or now). */
int io_temp_register(const char *path, char *err, size_t cap);
void io_temp_unregister(const char *path);
/** Unregister `dir` and every registered path below it (what a caller removed with it, or never
 *  created). The registry is the main thread's: call these from outside parallel regions. */
void io_temp_unregister_under(const char *dir);

/** Run argv[0] (an absolute path) with the arguments argv[1..] (NULL-terminated) as a child
 *  process, no shell, and wait for it. 0 when it exited with status 0; -1 otherwise (err says
 *  how it ended). */
int io_run(char *const argv[], char *err, size_t cap);

/** io_run() with the child's environment envp (NULL-terminated; NULL: this process's), its
 *  standard input /dev/null and its standard output and error both written to the file `log`
 *  (created or truncated), for a child whose report is read afterwards (POV-Ray's statistics).
 *  *cpu_s (may be NULL) gets the child's user + system CPU seconds (wait4's rusage), whatever
 *  its exit status. */
int io_run_logged(char *const argv[], char *const envp[], const char *log, double *cpu_s, char *err,
                  size_t cap);

/** Memory this process may still use without swapping: MemAvailable of /proc/meminfo (Linux),
 *  else the free physical pages. 0 when neither can be read (then nothing can be judged). */
size_t io_memory_available(void);

/** Parse a size such as 512M, 8G, 1.5G or 1000000 (bytes; K, M, G, T are powers of 1024) into
 *  *bytes; 1, or 0 when the text is not one. */
int io_parse_size(const char *text, size_t *bytes);

/** The whole of the file at path (malloc'ed; free() it), *len bytes of it followed by a NUL that
 *  *len does not count; NULL when it cannot be opened or read, or memory runs out. Reads to the
 *  end, so pipes and other files that cannot seek are read too. */
char *io_read_file(const char *path, size_t *len);

/** "11.8 GB" style (powers of 1024) for messages. */
void io_format_size(size_t bytes, char *buf, size_t cap);

/** io_atomic_open() for a CSV file, which then starts with the provenance as comment lines, before
 *  the header:
 *    # version: 0.1.0
 *    # commit: ccfbde6
 *    # date: 2026-12-06T10:00:00Z
 *    # command_line: pencil verify dispersion --quick --csv d.csv
 *  (control characters in the command line escaped as \n, \t, \xNN, so that it stays one line).
 *  Readers skip lines that start with '#' (docs/DEVELOPING.md, "Writing outputs"). */
int io_csv_open(io_atomic_t *a, const char *path, char *err, size_t cap);

/** Room for io_shortest()'s text. */
#define IO_SHORTEST_MAX 32
/** The shortest decimal text of v that reads back as v (%.Ng for the least N from the number of
 *  its integer digits to 17: 200, 0.1234567, 1e-323; "nan", "inf"), in
 *  buf[IO_SHORTEST_MAX]; returns buf. For values echoed in messages, CSV files and attributes,
 *  where %g would print 89.9999999999 as 90. */
const char *io_shortest(double v, char buf[IO_SHORTEST_MAX]);

/** Write s as one CSV field (RFC 4180: quoted, with doubled quotes, when it holds a comma, a
 *  quote, a line break or leading/trailing space). */
void io_csv_field(FILE *f, const char *s);

#endif
