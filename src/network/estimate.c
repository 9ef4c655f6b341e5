/* estimate.c: sizes and memory of a case before allocation (to be written). */
#include "ps_network.h"
