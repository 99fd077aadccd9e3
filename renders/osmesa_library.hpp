// The OSMesa and OpenGL 1.x functions the renderer calls, loaded from Mesa's libOSMesa when the
// first renderer is made instead of linked into every program.
//
// Why: libOSMesa brings in libLLVM, and resolving their symbols costs each start of a program
// that links them 0.1 to 0.25 s (docs/reliability.md, "CI time"), whether it draws or not. Most
// runs of `tumble` and of the tests never draw; they no longer pay it. The function types are
// taken from Mesa's own headers (decltype of the declarations), so a wrong signature cannot
// compile.
#pragma once

#define GL_GLEXT_PROTOTYPES 1
#include <GL/gl.h>
#include <GL/osmesa.h>

// Every entry point the renderer uses: add a function here before calling it.
#define TUMBLE_OSMESA_FUNCTIONS(X) \
  X(OSMesaCreateContextExt)        \
  X(OSMesaDestroyContext)          \
  X(OSMesaMakeCurrent)             \
  X(glBegin)                       \
  X(glBlendFunc)                   \
  X(glClear)                       \
  X(glClearColor)                  \
  X(glClearStencil)                \
  X(glColor4f)                     \
  X(glColorMaterial)               \
  X(glColorPointer)                \
  X(glCullFace)                    \
  X(glDepthFunc)                   \
  X(glDepthMask)                   \
  X(glDisable)                     \
  X(glDisableClientState)          \
  X(glDrawArrays)                  \
  X(glDrawElements)                \
  X(glEnable)                      \
  X(glEnableClientState)           \
  X(glEnd)                         \
  X(glFinish)                      \
  X(glFogf)                        \
  X(glFogfv)                       \
  X(glFogi)                        \
  X(glFrontFace)                   \
  X(glLightModelfv)                \
  X(glLightfv)                     \
  X(glLineWidth)                   \
  X(glLoadMatrixd)                 \
  X(glMaterialf)                   \
  X(glMaterialfv)                  \
  X(glMatrixMode)                  \
  X(glMultMatrixd)                 \
  X(glNormal3d)                    \
  X(glNormalPointer)               \
  X(glPointSize)                   \
  X(glPolygonOffset)               \
  X(glPopMatrix)                   \
  X(glPushMatrix)                  \
  X(glShadeModel)                  \
  X(glStencilFunc)                 \
  X(glStencilOp)                   \
  X(glVertex3d)                    \
  X(glVertexPointer)               \
  X(glViewport)

namespace tumble::render {

// One pointer per function of TUMBLE_OSMESA_FUNCTIONS, named as in OpenGL: `gl.glEnable(...)`.
struct OsMesaLibrary {
#define TUMBLE_OSMESA_POINTER(name) decltype(&::name) name = nullptr;
  TUMBLE_OSMESA_FUNCTIONS(TUMBLE_OSMESA_POINTER)
#undef TUMBLE_OSMESA_POINTER
};

// Loads libOSMesa on the first call (thread-safe) and keeps it for the life of the process.
// Throws std::runtime_error naming the library, the package that provides it and the loader's
// reason when it is missing or lacks a function; every later call then throws the same.
const OsMesaLibrary& osmesa_library();

}  // namespace tumble::render
