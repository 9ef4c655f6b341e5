/* main.c: the peristatic command line (placeholder while the solver grows). */
#include <stdio.h>
int main(void) { puts("peristatic"); return 0; }
