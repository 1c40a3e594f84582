/* test_args.c -- the pencil command's one argument parser (cli/args.c): --opt=value, --opt
 * value, -oFILE, -o FILE, "--", help anywhere before it, and the errors a user must see. */
#include <stdio.h>
#include <string.h>

#include "../cli/args.h"
#include "cmocka_main.h"

enum { OUT = 1, RHO, FLAG };
static const cli_spec_t specs[] = {
    {"--output", 'o', 1, OUT}, {"--rho", 0, 1, RHO}, {"--certified", 0, 0, FLAG}};

static int parse(int argc, char **argv, cli_arg_t *out) {
  return cli_parse("test", argc, argv, specs, 3, out);
}

static void values_in_every_spelling(void **state) {
  (void)state;
  char *argv[] = {"cmd",   "--rho=0.5", "-oa.exr", "--output",    "b.exr",     "-o",
                  "c.exr", "--rho",     "-1",      "--certified", "scene.json"};
  cli_arg_t a[16];
  int n = parse(11, argv, a);
  assert_int_equal(n, 7);
  assert_int_equal(a[0].spec->id, RHO);
  assert_string_equal(a[0].value, "0.5");
  assert_string_equal(a[1].value, "a.exr");
  assert_string_equal(a[1].name, "--output");
  assert_string_equal(a[2].value, "b.exr");
  assert_string_equal(a[3].value, "c.exr");
  assert_string_equal(a[4].value, "-1"); /* a value may start with '-' */
  assert_int_equal(a[5].spec->id, FLAG);
  assert_null(a[5].value);
  assert_null(a[6].spec);
  assert_string_equal(a[6].value, "scene.json");
}

static void double_dash_ends_options(void **state) {
  (void)state;
  char *argv[] = {"cmd", "--certified", "--", "--rho", "-", "--help"};
  cli_arg_t a[8];
  int n = parse(6, argv, a);
  assert_int_equal(n, 4);
  assert_null(a[1].spec);
  assert_string_equal(a[1].value, "--rho");
  assert_string_equal(a[2].value, "-");
  assert_string_equal(a[3].value, "--help"); /* positional after "--" */
}

static void help_anywhere(void **state) {
  (void)state;
  char *argv1[] = {"cmd", "--rho", "1", "-h"};
  char *argv2[] = {"cmd", "x", "--help", "--bogus"};
  cli_arg_t a[8];
  assert_int_equal(parse(4, argv1, a), CLI_ARGS_HELP);
  assert_int_equal(parse(4, argv2, a), CLI_ARGS_HELP);
}

static void errors(void **state) {
  (void)state;
  char *unknown[] = {"cmd", "--rh", "1"};
  char *missing[] = {"cmd", "--rho"};
  char *flagval[] = {"cmd", "--certified=yes"};
  char *shortbad[] = {"cmd", "-x"};
  cli_arg_t a[8];
  assert_int_equal(parse(3, unknown, a), -1); /* no abbreviations */
  assert_int_equal(parse(2, missing, a), -1);
  assert_int_equal(parse(2, flagval, a), -1);
  assert_int_equal(parse(2, shortbad, a), -1);
}

int main(int argc, char **argv) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(values_in_every_spelling),
      cmocka_unit_test(double_dash_ends_options),
      cmocka_unit_test(help_anywhere),
      cmocka_unit_test(errors),
  };
  if (argc > 1)
    cmocka_set_test_filter(argv[1]);
  return cmocka_run_group_tests(tests, NULL, NULL);
}
