#pragma once

// AVX2/FMA (x86-64-v3) and portable clones of a hot function, chosen once at load time by the
// CPU: the library stays portable and a modern CPU runs the wide code. The clones must stay out
// of line (GCC would otherwise inline the portable clone into its caller); Clang never inlines a
// multiversioned function and refuses noinline beside target_clones.
#if defined(__clang__)
#define GLINTSCOPE_OUT_OF_LINE_CLONES __attribute__((target_clones("arch=x86-64-v3", "default")))
#else
#define GLINTSCOPE_OUT_OF_LINE_CLONES [[gnu::noinline]] __attribute__((target_clones("arch=x86-64-v3", "default")))
#endif
