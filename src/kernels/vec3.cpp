// vec3.hpp is header-only; this translation unit checks that it compiles alone.
#include <fdem/kernels/vec3.hpp>
