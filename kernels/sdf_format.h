/* sdf_format.h: the brick pool's sample type for the compile-time FORMAT (0 int8 snorm, 1 int16 snorm,
 * 2 float32), shared by the kernels that write the pool and those that read it. */
#ifndef SDFBRICK_SDF_FORMAT_H
#define SDFBRICK_SDF_FORMAT_H

#if FORMAT == 0
typedef char sample_t;
#elif FORMAT == 1
typedef short sample_t;
#else
typedef float sample_t;
#endif

#endif /* SDFBRICK_SDF_FORMAT_H */
