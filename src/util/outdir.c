/* outdir.c: output folders owned by peristatic (to be written). */
#include "ps_util.h"
