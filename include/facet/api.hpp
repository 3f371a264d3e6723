// facet: what a shared libfacet exports. The library is compiled with hidden visibility, and every
// public header wraps its declarations in FACET_API_BEGIN ... FACET_API_END: libfacet.so exports
// exactly what include/facet declares (the inline templates' calls into the library among it) and
// nothing that only src/ declares. A new public header needs the pair too; the installed-library
// test (tests/install) links a program against the shared library and checks its exports.
#pragma once

#define FACET_API_BEGIN _Pragma("GCC visibility push(default)")
#define FACET_API_END _Pragma("GCC visibility pop")
