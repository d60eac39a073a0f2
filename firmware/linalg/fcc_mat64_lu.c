/* The double flavour (fcc_mat64_*) of fcc_mat_lu.c; see fcc_mat_impl.h. */
#define FCC_MAT_F64 1
#include "fcc_mat_lu.c"
