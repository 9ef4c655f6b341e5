/* plot.c: the gnuplot plots of the outputs (ps_report.h): a script
 * written beside the data, run by PS_GNUPLOT (found at configure time;
 * none: the script stays for the user) without a shell. */
#include "ps_report.h"

#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

#include "config.h"

const char *ps_gnuplot_quoted(const char *name, char *buf, size_t len) {
  size_t k = 0;
  for (const char *c = name; *c && k + 3 < len; c++) {
    if (*c == '\'') buf[k++] = '\'';
    buf[k++] = (unsigned char)*c < 0x20 || *c == 0x7f ? '?' : *c;
  }
  buf[k] = '\0';
  return buf;
}

int ps_gnuplot_run(const char *dir, const char *script) {
  if (!PS_GNUPLOT[0]) return -1;
  fflush(NULL);
  pid_t pid = fork();
  if (pid < 0) return -1;
  if (pid == 0) { /* only async-signal-safe calls between fork and exec */
    char *argv[] = {(char *)PS_GNUPLOT, (char *)script, NULL};
    int null = open("/dev/null", O_WRONLY | O_CLOEXEC); /* dup2's copy stays open */
    if (null >= 0) dup2(null, STDERR_FILENO);
    if (chdir(dir) != 0) _exit(127);
    execv(argv[0], argv); /* PS_GNUPLOT is an absolute path (configure) */
    _exit(127);
  }
  int st = 0;
  while (waitpid(pid, &st, 0) < 0)
    if (errno != EINTR) return -1;
  return WIFEXITED(st) && WEXITSTATUS(st) == 0 ? 0 : -1;
}

int ps_report_write_path_plot(const char *dir, const char *name, int with_displacement,
                              ps_ctx *ctx) {
  char path[1300], title[300];
  ps_outfile o;
  snprintf(path, sizeof path, "%s/path.gp", dir);
  PS_CHECK(ps_outfile_open(&o, path, ctx));
  fprintf(o.f,
          "# gnuplot script: the equilibrium path of history.csv\n"
          "set terminal pngcairo size 900,600 noenhanced\nset output 'path.png'\n"
          "set datafile separator ','\nset key top right\nset grid\n"
          "set title 'Equilibrium path: %s'\n",
          ps_gnuplot_quoted(name, title, sizeof title));
  if (with_displacement)
    fprintf(o.f,
            "set xlabel 'displacement (m)'\nset ylabel 'reaction (N/m in 2D, N in 3D)'\n"
            "plot 'history.csv' using \"displacement_m\":\"reaction\" with linespoints "
            "pt 7 ps 0.4 title 'reaction (one point per converged increment)'\n");
  else
    fprintf(o.f,
            "set xlabel 'increment'\nset ylabel 'boundary stress / sigma_y, load factor'\n"
            "plot 'history.csv' using \"step\":\"stress_over_sigma_y\" with linespoints "
            "pt 7 ps 0.4 title 'boundary stress / sigma_y', \\\n"
            "     'history.csv' using \"step\":\"load_factor\" with lines dt 2 "
            "title 'load factor'\n");
  return ps_outfile_commit(&o, ctx);
}
