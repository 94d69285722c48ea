/* curray cli: the scene that `curray --example` prints. */
#ifndef CR_CLI_EXAMPLE_H
#define CR_CLI_EXAMPLE_H

/* scenes/demo.yml, byte for byte, with a complete commented set of keys;
 * CMake writes its definition (example_scene.c in the build folder) from
 * the file when it configures, and again whenever the file changes. */
extern const char cr_example_scene[];

#endif
