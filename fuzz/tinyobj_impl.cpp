// The fuzz build compiles tinyobjloader's implementation itself, so that the parser runs with
// coverage feedback and under the sanitizers. These definitions take precedence over the ones of
// the Debian shared library (an executable's own symbols come first); the header is the same
// version (rc10). The normal build links the prebuilt library only.
#define TINYOBJLOADER_IMPLEMENTATION
#include <tiny_obj_loader.h>
