// core/raybench.cpp (in progress)
#include "core/raybench.h"
