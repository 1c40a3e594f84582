/* test_output.c -- io/output.h and io/json.h: output paths checked before work, files replaced
 * atomically with nothing left behind on failure, an EXR and its preview replaced together,
 * child processes without a shell, CSV quoting, and JSON that round-trips any string. */
#include <dirent.h>
#include <jansson.h>
#include <pthread.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "cmocka_main.h"
#include "io/image_io.h"
#include "io/json.h"
#include "io/output.h"

/* A fresh directory for one case. */
static void temp_dir(char *out, size_t cap) {
  snprintf(out, cap, "%s/pencil_test_output_XXXXXX", P_tmpdir);
  assert_non_null(mkdtemp(out));
}

/* Number of directory entries whose name starts with '.' (temporary files), other than . and
 * .. . */
static int hidden_files(const char *dir) {
  DIR *d = opendir(dir);
  int n = 0;
  assert_non_null(d);
  for (struct dirent *e; (e = readdir(d));)
    n += e->d_name[0] == '.' && strcmp(e->d_name, ".") != 0 && strcmp(e->d_name, "..") != 0;
  closedir(d);
  return n;
}

static void check_refuses_what_is_not_a_file(void **state) {
  (void)state;
  char dir[512], path[600], err[512];
  temp_dir(dir, sizeof dir);
  assert_int_equal(io_output_check(dir, err, sizeof err), -1);
  assert_non_null(strstr(err, "a directory"));
  assert_int_equal(io_output_check("/dev/null", err, sizeof err), -1);
  assert_non_null(strstr(err, "device"));
  assert_int_equal(io_output_check("/nonexistent-dir/x.json", err, sizeof err), -1);
  assert_non_null(strstr(err, "/nonexistent-dir"));
  assert_int_equal(io_output_check("", err, sizeof err), -1);
  snprintf(path, sizeof path, "%s/new.json", dir);
  assert_int_equal(io_output_check(path, err, sizeof err), 0);
  rmdir(dir);
}

static void atomic_write_replaces_whole_or_not_at_all(void **state) {
  (void)state;
  char dir[512], path[600], err[512], buf[64] = "";
  temp_dir(dir, sizeof dir);
  snprintf(path, sizeof path, "%s/f.txt", dir);
  FILE *f = fopen(path, "w");
  fputs("old", f);
  fclose(f);
  io_atomic_t a;
  assert_int_equal(io_atomic_open(&a, path, err, sizeof err), 0);
  fputs("new", a.f);
  assert_int_equal(hidden_files(dir), 1); /* the temporary file, beside the target */
  io_atomic_abort(&a);
  assert_int_equal(hidden_files(dir), 0);
  f = fopen(path, "r");
  assert_non_null(fgets(buf, sizeof buf, f));
  fclose(f);
  assert_string_equal(buf, "old");
  assert_int_equal(io_atomic_open(&a, path, err, sizeof err), 0);
  fputs("new", a.f);
  assert_int_equal(io_atomic_commit(&a, err, sizeof err), 0);
  f = fopen(path, "r");
  assert_non_null(fgets(buf, sizeof buf, f));
  fclose(f);
  assert_string_equal(buf, "new");
  assert_int_equal(hidden_files(dir), 0);
  remove(path);
  rmdir(dir);
}

/* A failed EXR (an extra channel duplicating a name) leaves the old EXR and preview and no
 * temporary file; a good write replaces both. */
static void render_write_keeps_old_files_on_failure(void **state) {
  (void)state;
  char dir[512], exr[600], png[600], err[512];
  temp_dir(dir, sizeof dir);
  snprintf(exr, sizeof exr, "%s/r.exr", dir);
  snprintf(png, sizeof png, "%s/r.png", dir);
  FILE *f = fopen(exr, "w");
  fputs("old exr", f);
  fclose(f);
  f = fopen(png, "w");
  fputs("old png", f);
  fclose(f);
  rt_image_t img;
  assert_int_equal(rt_image_alloc(&img, 4, 3), RT_OK);
  const io_exr_channel_t dup[] = {{"R", img.ch[RT_CH_G]}};
  assert_int_equal(io_render_write(exr, &img, dup, 1, NULL, 0, err, sizeof err), -1);
  assert_non_null(strstr(err, "duplicates"));
  struct stat st;
  assert_int_equal(stat(exr, &st), 0);
  assert_int_equal(st.st_size, 7);
  assert_int_equal(stat(png, &st), 0);
  assert_int_equal(st.st_size, 7);
  assert_int_equal(hidden_files(dir), 0);
  assert_int_equal(io_render_write(exr, &img, NULL, 0, NULL, 0, err, sizeof err), 0);
  assert_int_equal(stat(exr, &st), 0);
  assert_true(st.st_size > 7);
  assert_int_equal(stat(png, &st), 0);
  assert_true(st.st_size > 7);
  assert_int_equal(io_render_check("x.png", err, sizeof err), -1);
  assert_int_equal(io_render_check(".exr", err, sizeof err), -1);
  rt_image_free(&img);
  remove(exr);
  remove(png);
  rmdir(dir);
}

static void run_reports_exit_status_without_a_shell(void **state) {
  (void)state;
  char err[256];
  char *ok[] = {"/bin/true", NULL}, *bad[] = {"/bin/false", NULL};
  char *odd[] = {"/bin/test", "a'b; touch x", "=", "a'b; touch x", NULL}; /* no shell parses it */
  assert_int_equal(io_run(ok, err, sizeof err), 0);
  assert_int_equal(io_run(bad, err, sizeof err), -1);
  assert_non_null(strstr(err, "status 1"));
  assert_int_equal(io_run(odd, err, sizeof err), 0);
  char *missing[] = {"/nonexistent/program", NULL};
  assert_int_equal(io_run(missing, err, sizeof err), -1);
}

/* A child run by io_run() writes to the same standard output after what this process wrote
 * before it, though stdout to a file is fully buffered (its buffer is flushed first). */
static void run_child_output_after_ours(void **state) {
  (void)state;
  char dir[512], out[600], err[256], text[64] = {0};
  temp_dir(dir, sizeof dir);
  snprintf(out, sizeof out, "%s/out", dir);
  pid_t pid = fork();
  assert_true(pid >= 0);
  if (pid == 0) {
    if (!freopen(out, "w", stdout))
      _exit(3);
    fputs("ours\n", stdout);
    char *argv[] = {"/bin/echo", "child", NULL};
    _exit(io_run(argv, err, sizeof err) == 0 && fflush(stdout) == 0 ? 0 : 4);
  }
  int status = 0;
  assert_int_equal(waitpid(pid, &status, 0), pid);
  assert_true(WIFEXITED(status) && WEXITSTATUS(status) == 0);
  FILE *f = fopen(out, "r");
  assert_non_null(f);
  size_t n = fread(text, 1, sizeof text - 1, f);
  fclose(f);
  text[n] = 0;
  assert_string_equal(text, "ours\nchild\n");
  remove(out);
  rmdir(dir);
}

/* A logged child: its output and errors in the log, its environment the one given, its CPU
 * time reported (a busy loop of the shell's: more than nothing, less than the wall clock's
 * bound of the test). */
static void run_logged_keeps_output_environment_and_cpu(void **state) {
  (void)state;
  char dir[512], log[600], err[256];
  temp_dir(dir, sizeof dir);
  snprintf(log, sizeof log, "%s/child.log", dir);
  char *argv[] = {"/bin/sh", "-c",
                  "echo out:$PENCIL_X; echo err >&2; i=0; while [ $i -lt 20000 ]; do "
                  "i=$((i+1)); done",
                  NULL};
  char *envp[] = {"PENCIL_X=42", NULL};
  double cpu = -1.0;
  assert_int_equal(io_run_logged(argv, envp, log, &cpu, err, sizeof err), 0);
  assert_true(cpu > 0.0 && cpu < 60.0);
  size_t len;
  char *text = io_read_file(log, &len);
  assert_non_null(text);
  assert_non_null(strstr(text, "out:42\n"));
  assert_non_null(strstr(text, "err\n"));
  free(text);
  char *bad[] = {"/bin/sh", "-c", "exit 3", NULL};
  assert_int_equal(io_run_logged(bad, NULL, log, NULL, err, sizeof err), -1);
  assert_non_null(strstr(err, "status 3"));
  unlink(log);
  rmdir(dir);
}

static void csv_fields_are_quoted_when_needed(void **state) {
  (void)state;
  char buf[256] = "";
  FILE *f = fmemopen(buf, sizeof buf, "w");
  io_csv_field(f, "plain");
  fputc('|', f);
  io_csv_field(f, "a,b");
  fputc('|', f);
  io_csv_field(f, "say \"hi\"");
  fputc('|', f);
  io_csv_field(f, " pad");
  fclose(f);
  assert_string_equal(buf, "plain|\"a,b\"|\"say \"\"hi\"\"\"|\" pad\"");
}

static void json_round_trips_any_string_and_carries_provenance(void **state) {
  (void)state;
  char dir[512], path[600], err[512];
  const char *odd = "q'uo\"te\\back\tslash \xc3\xa9t\xc3\xa9";
  char *argv[] = {"pencil", "sweep", "--out", (char *)odd, NULL};
  io_provenance_set("9.9.9", "abc123", 4, argv);
  temp_dir(dir, sizeof dir);
  snprintf(path, sizeof path, "%s/s.json", dir);
  json_t *root = json_pack("{s:s, s:o}", "scene", odd, "nan", io_json_number(0.0 / 0.0));
  assert_int_equal(io_json_write(path, root, err, sizeof err), 0);
  json_decref(root);
  json_error_t je;
  json_t *back = json_load_file(path, 0, &je);
  assert_non_null(back);
  assert_string_equal(json_string_value(json_object_get(back, "scene")), odd);
  assert_true(json_is_null(json_object_get(back, "nan")));
  json_t *prov = json_object_get(back, "provenance");
  assert_string_equal(json_string_value(json_object_get(prov, "version")), "9.9.9");
  assert_string_equal(json_string_value(json_object_get(prov, "commit")), "abc123");
  const char *cl = json_string_value(json_object_get(prov, "command_line"));
  assert_non_null(strstr(cl, "pencil sweep --out '"));
  assert_non_null(strstr(cl, "'\\''")); /* the quote, shell-quoted: the line can be re-run */
  json_decref(back);
  remove(path);
  rmdir(dir);
}

/* An interrupted write (SIGINT while the temporary file is open) leaves nothing behind, and the
 * process still dies of the signal. */
static void interrupted_write_leaves_no_temporary(void **state) {
  (void)state;
  char dir[512], path[600], err[512];
  temp_dir(dir, sizeof dir);
  snprintf(path, sizeof path, "%s/x.exr", dir);
  pid_t pid = fork();
  assert_true(pid >= 0);
  if (pid == 0) {
    io_atomic_t a;
    io_cleanup_on_signals();
    if (io_atomic_open(&a, path, err, sizeof err) != 0)
      _exit(3);
    fputs("half a file", a.f);
    fflush(a.f);
    raise(SIGINT);
    _exit(4); /* not reached */
  }
  int status = 0;
  assert_int_equal(waitpid(pid, &status, 0), pid);
  assert_true(WIFSIGNALED(status) && WTERMSIG(status) == SIGINT);
  assert_int_equal(hidden_files(dir), 0);
  assert_int_equal(access(path, F_OK), -1);
  rmdir(dir);
}

/* Registered temporaries of a child process's private directory go on a signal: files, then the
 * directories they emptied, nested, whatever the order of registration (here a file is
 * registered after its directory is unregistered and registered again, so its slot comes first);
 * an unregistered path stays. */
static void interrupted_run_removes_registered_directories(void **state) {
  (void)state;
  char dir[512], sub[600], deep[700], f1[800], f2[800], keep[600];
  temp_dir(dir, sizeof dir);
  snprintf(sub, sizeof sub, "%s/private", dir);
  snprintf(deep, sizeof deep, "%s/a", sub);
  snprintf(f1, sizeof f1, "%s/x.pov", deep);
  snprintf(f2, sizeof f2, "%s/y.log", sub);
  snprintf(keep, sizeof keep, "%s/kept", dir);
  pid_t pid = fork();
  assert_true(pid >= 0);
  if (pid == 0) {
    io_cleanup_on_signals();
    if (mkdir(sub, 0700) != 0 || mkdir(deep, 0700) != 0)
      _exit(3);
    char err[512];
    if (io_temp_register(sub, err, sizeof err) != 0 ||
        io_temp_register(deep, err, sizeof err) != 0 || io_temp_register(f2, err, sizeof err) != 0)
      _exit(6);
    io_temp_unregister(sub); /* its slot is taken again after its contents' */
    if (io_temp_register(f1, err, sizeof err) != 0 || io_temp_register(sub, err, sizeof err) != 0 ||
        io_temp_register(f1, err, sizeof err) != 0) /* twice: held once */
      _exit(7);
    FILE *a = fopen(f1, "w"), *b = fopen(f2, "w"), *c = fopen(keep, "w");
    if (!a || !b || !c)
      _exit(4);
    fclose(a);
    fclose(b);
    fclose(c);
    raise(SIGTERM);
    _exit(5); /* not reached */
  }
  int status = 0;
  assert_int_equal(waitpid(pid, &status, 0), pid);
  assert_true(WIFSIGNALED(status) && WTERMSIG(status) == SIGTERM);
  assert_int_equal(access(sub, F_OK), -1);
  assert_int_equal(access(keep, F_OK), 0);
  remove(keep);
  rmdir(dir);
}

/* A thread that waits with the clean-up's signals open, as an OpenMP worker does. */
static void *open_to_signals(void *arg) {
  (void)arg;
  for (;;)
    pause();
  return NULL;
}

/* A signal sent while the main thread holds the signals (here: between making a file and
 * registering it, as an atomic write does) goes to another thread that does not; the clean-up
 * passes it on to the main thread, so that the process dies only once the file is registered, and
 * the file goes with it. Without the hand-over the worker's handler ends the process inside the
 * window and the file stays. */
static void signal_in_a_worker_waits_for_the_main_thread(void **state) {
  (void)state;
  char dir[512], f1[600];
  temp_dir(dir, sizeof dir);
  snprintf(f1, sizeof f1, "%s/made-then-registered", dir);
  pid_t pid = fork();
  assert_true(pid >= 0);
  if (pid == 0) {
    io_cleanup_on_signals();
    pthread_t worker;
    if (pthread_create(&worker, NULL, open_to_signals, NULL) != 0)
      _exit(3);
    sigset_t all, old;
    sigfillset(&all);
    pthread_sigmask(SIG_BLOCK, &all, &old);
    FILE *f = fopen(f1, "w");
    if (!f || fclose(f) != 0)
      _exit(4);
    kill(getpid(), SIGTERM); /* only the worker can take it now */
    struct timespec t = {0, 200 * 1000 * 1000};
    nanosleep(&t, NULL); /* time for the worker's handler to run */
    char err[512];
    if (io_temp_register(f1, err, sizeof err) != 0)
      _exit(5);
    pthread_sigmask(SIG_SETMASK, &old, NULL);
    for (;;)
      pause(); /* the signal ends the process here */
  }
  int status = 0;
  assert_int_equal(waitpid(pid, &status, 0), pid);
  assert_true(WIFSIGNALED(status) && WTERMSIG(status) == SIGTERM);
  assert_int_equal(access(f1, F_OK), -1);
  remove(f1);
  rmdir(dir);
}

/* The clean-up holds 64 paths: the 65th is refused with a message, and so is an atomic write
 * that would need one more (it leaves no temporary file), until a slot is free again; a path held
 * already and a path too long to hold are answered too. In a child: the registry is the
 * process's. */
static void temporaries_beyond_the_registry_are_refused(void **state) {
  (void)state;
  char dir[512];
  temp_dir(dir, sizeof dir);
  pid_t pid = fork();
  assert_true(pid >= 0);
  if (pid == 0) {
    char path[700], err[512] = "", out[700], tmp_err[512] = "", longp[5000];
    for (int k = 0; k < 64; k++) {
      snprintf(path, sizeof path, "%s/t%02d", dir, k);
      if (io_temp_register(path, err, sizeof err) != 0)
        _exit(10);
    }
    if (io_temp_register(path, err, sizeof err) != 0) /* held already */
      _exit(11);
    snprintf(path, sizeof path, "%s/one-more", dir);
    if (io_temp_register(path, err, sizeof err) != -1 || !strstr(err, "64 temporary paths") ||
        !strstr(err, "one-more"))
      _exit(12);
    io_atomic_t a;
    snprintf(out, sizeof out, "%s/out.json", dir);
    if (io_atomic_begin(&a, out, tmp_err, sizeof tmp_err) != -1 || !strstr(tmp_err, "out.json") ||
        hidden_files(dir) != 0 || access(out, F_OK) == 0)
      _exit(13);
    snprintf(path, sizeof path, "%s/t05", dir);
    io_temp_unregister(path);
    if (io_atomic_begin(&a, out, tmp_err, sizeof tmp_err) != 0 ||
        io_atomic_commit(&a, tmp_err, sizeof tmp_err) != 0 || access(out, F_OK) != 0)
      _exit(14);
    remove(out);
    memset(longp, 'a', sizeof longp - 1);
    longp[sizeof longp - 1] = '\0';
    if (io_temp_register(longp, err, sizeof err) != -1 || !strstr(err, "too long"))
      _exit(15);
    _exit(0);
  }
  int status = 0;
  assert_int_equal(waitpid(pid, &status, 0), pid);
  assert_true(WIFEXITED(status));
  assert_int_equal(WEXITSTATUS(status), 0);
  assert_int_equal(hidden_files(dir), 0);
  rmdir(dir);
}

/* Whether process pid is gone (or a zombie no one reaps yet: it runs no more). */
static int gone(pid_t pid) {
  char path[64], stat[256] = "";
  snprintf(path, sizeof path, "/proc/%d/stat", (int)pid);
  FILE *f = fopen(path, "r");
  if (!f)
    return kill(pid, 0) != 0;
  size_t n = fread(stat, 1, sizeof stat - 1, f);
  fclose(f);
  stat[n] = '\0';
  const char *end = strrchr(stat, ')'); /* "pid (comm) S ..." */
  return end && end[1] == ' ' && end[2] == 'Z';
}

/* A child that io_run() waits for is stopped by the signal clean-up: the process dies of SIGTERM
 * and the child (a shell that wrote its pid and became `sleep 30`) is gone within 5 s. */
static void interrupted_run_stops_its_child(void **state) {
  (void)state;
  char dir[512], pidf[600], tmp[620], cmd[2000], err[256];
  temp_dir(dir, sizeof dir);
  snprintf(pidf, sizeof pidf, "%s/pid", dir);
  snprintf(tmp, sizeof tmp, "%s/pid.tmp", dir);
  pid_t pid = fork();
  assert_true(pid >= 0);
  if (pid == 0) {
    io_cleanup_on_signals();
    snprintf(cmd, sizeof cmd, "echo $$ > '%s' && mv '%s' '%s' && exec sleep 30", tmp, tmp, pidf);
    char *argv[] = {"/bin/sh", "-c", cmd, NULL};
    io_run(argv, err, sizeof err);
    _exit(3); /* not reached: the signal ends this process */
  }
  int sleeper = 0;
  for (int k = 0; k < 1000 && !sleeper; k++) { /* up to 10 s for the shell to start */
    FILE *f = fopen(pidf, "r");
    if (f) {
      if (fscanf(f, "%d", &sleeper) != 1)
        sleeper = 0;
      fclose(f);
    }
    if (!sleeper)
      usleep(10000);
  }
  assert_true(sleeper > 0);
  assert_int_equal(kill(pid, SIGTERM), 0);
  int status = 0;
  assert_int_equal(waitpid(pid, &status, 0), pid);
  assert_true(WIFSIGNALED(status) && WTERMSIG(status) == SIGTERM);
  int stopped = 0;
  for (int k = 0; k < 500 && !stopped; k++) {
    stopped = gone(sleeper);
    if (!stopped)
      usleep(10000);
  }
  if (!stopped)
    kill(sleeper, SIGKILL); /* leave nothing running, then fail */
  assert_true(stopped);
  remove(pidf);
  rmdir(dir);
}

static void sizes_parse_and_print(void **state) {
  (void)state;
  size_t b = 0;
  char buf[32];
  assert_int_equal(io_parse_size("512M", &b), 1);
  assert_true(b == 512u * 1024u * 1024u);
  assert_int_equal(io_parse_size("1.5G", &b), 1);
  assert_true(b == (size_t)(1.5 * 1024 * 1024 * 1024));
  assert_int_equal(io_parse_size("1000", &b), 1);
  assert_true(b == 1000);
  assert_int_equal(io_parse_size("8Q", &b), 0);
  assert_int_equal(io_parse_size("-1G", &b), 0);
  assert_int_equal(io_parse_size("G", &b), 0);
  assert_int_equal(io_parse_size("0", &b), 0);
  io_format_size((size_t)12670000000ull, buf, sizeof buf);
  assert_string_equal(buf, "11.8 GB");
  io_format_size(100, buf, sizeof buf);
  assert_string_equal(buf, "100 bytes");
  assert_true(io_memory_available() > 0); /* Linux: /proc/meminfo */
}

int main(int argc, char **argv) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(check_refuses_what_is_not_a_file),
      cmocka_unit_test(atomic_write_replaces_whole_or_not_at_all),
      cmocka_unit_test(render_write_keeps_old_files_on_failure),
      cmocka_unit_test(run_reports_exit_status_without_a_shell),
      cmocka_unit_test(run_child_output_after_ours),
      cmocka_unit_test(run_logged_keeps_output_environment_and_cpu),
      cmocka_unit_test(csv_fields_are_quoted_when_needed),
      cmocka_unit_test(json_round_trips_any_string_and_carries_provenance),
      cmocka_unit_test(sizes_parse_and_print),
      cmocka_unit_test(interrupted_write_leaves_no_temporary),
      cmocka_unit_test(interrupted_run_removes_registered_directories),
      cmocka_unit_test(interrupted_run_stops_its_child),
      cmocka_unit_test(temporaries_beyond_the_registry_are_refused),
      cmocka_unit_test(signal_in_a_worker_waits_for_the_main_thread),
  };
  if (argc > 1)
    cmocka_set_test_filter(argv[1]);
  return cmocka_run_group_tests(tests, NULL, NULL);
}
