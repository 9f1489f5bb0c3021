// Flat float records of evaluation kernels, declared once per kernel.
//
// An evaluation kernel runs one shared function on a record of floats and
// writes a record of results, identically on the CPU (the C++ build) and in
// a compute shader; parity tests compare the two. Each kernel's record
// layouts are declared ONCE, as FIELD LISTS: a macro taking a macro F and
// expanding to F(type, name, doc) for every field, in record order:
//
//   #define SG_FEAT_EVAL_OUT(F) F(float, dist, ("distance, texels")) F(vec2, grad, ("unit"))
//
// From a field list, this file generates the GLSL (and C++) code that reads
// the fields into locals and writes them back (SG_REC_READ, SG_REC_RETURN);
// surfgrad/bump/record.h generates the C++ table of names, widths, slots and
// docs (SG_REC_FIELDS). A module's kernel LIST is a second macro, one entry
// per kernel, X(name, id, function, IN, OUT, ...) (see
// shaders/sg/eval/kernels.glsl), from which the GLSL dispatch, the C++
// table and the parity tests are produced: adding a kernel is one entry and
// its two field lists. docs/architecture.md describes the convention.
//
// Field types and the floats they take:
//   float, int, bool  1 (int: an exact integer; bool: 0 or 1)
//   vec2, vec3, vec4  2, 3, 4
//   mat4              16, column by column (inputs only)
//   uint              2: its low and high 16 bits, each an exact integer, so
//                     a 32-bit word survives the binary32 record
// A kernel function names its input record parameter `sgRecIn`; the output
// fields are locals the function declares (SG_REC_DECLARE) and assigns.
// The `doc` argument is a string literal in parentheses, never expanded into
// GLSL code: GLSL preprocessors do not know string literals, so a comma
// inside one would split the argument (parentheses keep it whole; keep them
// balanced inside the string). Mesa's preprocessor also mis-splits strings
// holding < > or #, so docs avoid those and quote characters. After the
// string, inside the same parentheses, a module's C++ table may read
// options of its own (bump's: surfgrad/bump/eval_kernels.h); GLSL ignores them.
#ifndef SG_RECORD_GLSL
#define SG_RECORD_GLSL

#include "sg/compat.glsl"

// Readers and writers of one record type pair (struct IN_T { float v[N]; }
// and struct OUT_T { float v[M]; }), defined once per module.
#define SG_REC_DEFINE_IO(IN_T, OUT_T, OUT_N)                                                          \
    SG_FN void sgRecRead(IN_T x, SG_INOUT(int) at, SG_OUT(float) r) {                                 \
        r = x.v[at];                                                                                  \
        at += 1;                                                                                      \
    }                                                                                                 \
    SG_FN void sgRecRead(IN_T x, SG_INOUT(int) at, SG_OUT(int) r) {                                   \
        r = int(x.v[at]);                                                                             \
        at += 1;                                                                                      \
    }                                                                                                 \
    SG_FN void sgRecRead(IN_T x, SG_INOUT(int) at, SG_OUT(bool) r) {                                  \
        r = x.v[at] != 0.0f;                                                                          \
        at += 1;                                                                                      \
    }                                                                                                 \
    SG_FN void sgRecRead(IN_T x, SG_INOUT(int) at, SG_OUT(uint) r) {                                  \
        r = uint(max(x.v[at], 0.0f)) | (uint(max(x.v[at + 1], 0.0f)) << 16u);                         \
        at += 2;                                                                                      \
    }                                                                                                 \
    SG_FN void sgRecRead(IN_T x, SG_INOUT(int) at, SG_OUT(vec2) r) {                                  \
        r = vec2(x.v[at], x.v[at + 1]);                                                               \
        at += 2;                                                                                      \
    }                                                                                                 \
    SG_FN void sgRecRead(IN_T x, SG_INOUT(int) at, SG_OUT(vec3) r) {                                  \
        r = vec3(x.v[at], x.v[at + 1], x.v[at + 2]);                                                  \
        at += 3;                                                                                      \
    }                                                                                                 \
    SG_FN void sgRecRead(IN_T x, SG_INOUT(int) at, SG_OUT(vec4) r) {                                  \
        r = vec4(x.v[at], x.v[at + 1], x.v[at + 2], x.v[at + 3]);                                     \
        at += 4;                                                                                      \
    }                                                                                                 \
    SG_FN void sgRecRead(IN_T x, SG_INOUT(int) at, SG_OUT(mat4) r) {                                  \
        r = mat4(vec4(x.v[at], x.v[at + 1], x.v[at + 2], x.v[at + 3]),                               \
                 vec4(x.v[at + 4], x.v[at + 5], x.v[at + 6], x.v[at + 7]),                           \
                 vec4(x.v[at + 8], x.v[at + 9], x.v[at + 10], x.v[at + 11]),                         \
                 vec4(x.v[at + 12], x.v[at + 13], x.v[at + 14], x.v[at + 15]));                      \
        at += 16;                                                                                     \
    }                                                                                                 \
    SG_FN void sgRecWrite(SG_INOUT(OUT_T) y, SG_INOUT(int) at, float a) {                             \
        y.v[at] = a;                                                                                  \
        at += 1;                                                                                      \
    }                                                                                                 \
    SG_FN void sgRecWrite(SG_INOUT(OUT_T) y, SG_INOUT(int) at, int a) {                               \
        y.v[at] = float(a);                                                                           \
        at += 1;                                                                                      \
    }                                                                                                 \
    SG_FN void sgRecWrite(SG_INOUT(OUT_T) y, SG_INOUT(int) at, vec2 a) {                              \
        y.v[at] = a.x;                                                                                \
        y.v[at + 1] = a.y;                                                                            \
        at += 2;                                                                                      \
    }                                                                                                 \
    SG_FN void sgRecWrite(SG_INOUT(OUT_T) y, SG_INOUT(int) at, vec3 a) {                              \
        y.v[at] = a.x;                                                                                \
        y.v[at + 1] = a.y;                                                                            \
        y.v[at + 2] = a.z;                                                                            \
        at += 3;                                                                                      \
    }                                                                                                 \
    SG_FN void sgRecClear(SG_OUT(OUT_T) y) {                                                          \
        for (int i = 0; i < OUT_N; ++i) y.v[i] = 0.0f;                                                \
    }

#define SG_REC_READ_FIELD(T, name, doc)                                                               \
    T name;                                                                                           \
    sgRecRead(sgRecIn, sgRecAt, name);
#define SG_REC_DECLARE_FIELD(T, name, doc) T name;
#define SG_REC_WRITE_FIELD(T, name, doc) sgRecWrite(sgRecOut, sgRecAt, name);

// Declares a local per field of LIST and reads it from `sgRecIn`.
#define SG_REC_READ(LIST)                                                                             \
    int sgRecAt = 0;                                                                                  \
    LIST(SG_REC_READ_FIELD)
// Declares a local per field of LIST (the outputs the kernel assigns).
#define SG_REC_DECLARE(LIST) LIST(SG_REC_DECLARE_FIELD)
// Writes the locals named after LIST's fields into a zeroed OUT_T and
// returns it.
#define SG_REC_RETURN(OUT_T, LIST)                                                                    \
    OUT_T sgRecOut;                                                                                   \
    sgRecClear(sgRecOut);                                                                             \
    sgRecAt = 0;                                                                                      \
    LIST(SG_REC_WRITE_FIELD)                                                                          \
    return sgRecOut;

#endif
