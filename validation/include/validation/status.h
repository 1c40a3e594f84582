/* status.h -- what a validation driver's failure was, so that the command's exit code can say
 * whether its input was wrong (2) or the work failed (1: out of memory, a render or a write that
 * failed). Every failure prints its reason on stderr first. */
#ifndef VALIDATION_STATUS_H
#define VALIDATION_STATUS_H

/** Another failure than the two below: the work or a write after it failed. */
#define VAL_EFAIL (-1)
/** The scene file could not be read, or the scene it holds not built. */
#define VAL_ESCENE (-2)
/** An output cannot be written (its directory cannot be made, it is a directory, it is the scene
 *  read, ...); found before any work, nothing written. */
#define VAL_EOUTPUT (-3)

#endif
