/* griffith.c: the Griffith sweep (to be moved here from run.c). */
#include "ps_app.h"
