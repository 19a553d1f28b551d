#include "brushwork/render/gl_name.hpp"

#include "brushwork/render/context.hpp"
#include "gl_api.hpp"

namespace brushwork {
namespace {

// glGen* and glDelete* of each kind
template <GlKind K> struct GlCalls;
template <> struct GlCalls<GlKind::texture> {
  static void gen(GLuint* id) { gl::GenTextures(1, id); }
  static void del(const GLuint* id) { gl::DeleteTextures(1, id); }
};
template <> struct GlCalls<GlKind::framebuffer> {
  static void gen(GLuint* id) { gl::GenFramebuffers(1, id); }
  static void del(const GLuint* id) { gl::DeleteFramebuffers(1, id); }
};
template <> struct GlCalls<GlKind::renderbuffer> {
  static void gen(GLuint* id) { gl::GenRenderbuffers(1, id); }
  static void del(const GLuint* id) { gl::DeleteRenderbuffers(1, id); }
};
template <> struct GlCalls<GlKind::vertex_array> {
  static void gen(GLuint* id) { gl::GenVertexArrays(1, id); }
  static void del(const GLuint* id) { gl::DeleteVertexArrays(1, id); }
};
template <> struct GlCalls<GlKind::buffer> {
  static void gen(GLuint* id) { gl::GenBuffers(1, id); }
  static void del(const GLuint* id) { gl::DeleteBuffers(1, id); }
};

// the context is open and current on this thread (false: it took its objects along, or it
// belongs to another thread, where deleting would be wrong)
bool usable(const RenderContext* ctx) {
  if (!ctx || ctx->closed()) return false;
  try {
    ctx->make_current();
  } catch (...) {
    return false;
  }
  return true;
}

}  // namespace

template <GlKind K>
void GlName<K>::reset(const RenderContext* ctx, unsigned id) {
  if (id_ && usable(ctx_)) GlCalls<K>::del(&id_);
  ctx_ = ctx;
  id_ = id;
}

template <GlKind K>
void GlName<K>::generate(const RenderContext* ctx) {
  GLuint id = 0;
  GlCalls<K>::gen(&id);
  reset(ctx, id);
}

template class GlName<GlKind::texture>;
template class GlName<GlKind::framebuffer>;
template class GlName<GlKind::renderbuffer>;
template class GlName<GlKind::vertex_array>;
template class GlName<GlKind::buffer>;

}  // namespace brushwork
