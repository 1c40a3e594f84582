/* test_args.c -- the pencil command's one argument parser (cli/args.c): --opt=value, --opt
 * value, -oFILE, -o FILE, "--", help anywhere before it, an option given twice, and the errors a
 * user must see. */
#include <stdio.h>
#include <string.h>

#include "../cli/args.h"
#include "cmocka_main.h"

enum { OUT = 1, RHO, FLAG, RECEIVER };
static const cli_spec_t specs[] = {{"--output", 'o', 1, OUT},
                                   {"--rho", 0, 1, RHO},
                                   {"--certified", 0, 0, FLAG},
                                   {"--receiver", 0, CLI_REPEATED, RECEIVER}};

static int parse(int argc, char **argv, cli_arg_t *out) {
  return cli_parse("test", argc, argv, specs, 4, out);
}

static void values_in_every_spelling(void **state) {
  (void)state;
  char *argv1[] = {"cmd", "--rho=0.5", "-oa.exr", "--certified", "scene.json"};
  char *argv2[] = {"cmd", "--output", "b.exr", "--rho", "-1"};
  char *argv3[] = {"cmd", "-o", "c.exr"};
  cli_arg_t a[16];
  assert_int_equal(parse(5, argv1, a), 4);
  assert_int_equal(a[0].spec->id, RHO);
  assert_string_equal(a[0].value, "0.5");
  assert_string_equal(a[1].value, "a.exr");
  assert_string_equal(a[1].name, "--output");
  assert_int_equal(a[2].spec->id, FLAG);
  assert_null(a[2].value);
  assert_null(a[3].spec);
  assert_string_equal(a[3].value, "scene.json");
  assert_int_equal(parse(5, argv2, a), 2);
  assert_string_equal(a[0].value, "b.exr");
  assert_string_equal(a[1].value, "-1"); /* a value may start with '-' */
  assert_int_equal(parse(3, argv3, a), 1);
  assert_string_equal(a[0].value, "c.exr");
}

/* An option given twice is refused, whatever its spelling (the last would win silently), unless
 * it is one that is repeated by design (--receiver). */
static void repeated_option_refused(void **state) {
  (void)state;
  char *twice[] = {"cmd", "--rho", "1", "--rho=2"};
  char *spellings[] = {"cmd", "-oa.exr", "--output", "b.exr"};
  char *flag[] = {"cmd", "--certified", "x", "--certified"};
  char *receivers[] = {"cmd", "--receiver", "a", "--receiver", "b"};
  cli_arg_t a[8];
  assert_int_equal(parse(4, twice, a), -1);
  assert_int_equal(parse(4, spellings, a), -1);
  assert_int_equal(parse(4, flag, a), -1);
  assert_int_equal(parse(5, receivers, a), 2);
  assert_string_equal(a[1].value, "b");
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
      cmocka_unit_test(repeated_option_refused),
      cmocka_unit_test(double_dash_ends_options),
      cmocka_unit_test(help_anywhere),
      cmocka_unit_test(errors),
  };
  if (argc > 1)
    cmocka_set_test_filter(argv[1]);
  return cmocka_run_group_tests(tests, NULL, NULL);
}
