#include "brushwork/render/gl_name.hpp"

#include "brushwork/render/context.hpp"
#include "gl_api.hpp"

namespace brushwork {
namespace {

// glGen* and glDelete* of each kind, in GlKind's order (entries of the GL table, loaded at run time)
struct GlCalls {
  void (**gen)(GLsizei, GLuint*);
  void (**del)(GLsizei, const GLuint*);
};
const GlCalls kCalls[] = {{&gl::GenTextures, &gl::DeleteTextures},
                          {&gl::GenFramebuffers, &gl::DeleteFramebuffers},
                          {&gl::GenRenderbuffers, &gl::DeleteRenderbuffers},
                          {&gl::GenVertexArrays, &gl::DeleteVertexArrays},
                          {&gl::GenBuffers, &gl::DeleteBuffers}};

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
  if (id_ && usable(ctx_)) (*kCalls[static_cast<int>(K)].del)(1, &id_);
  ctx_ = ctx;
  id_ = id;
}

template <GlKind K>
void GlName<K>::generate(const RenderContext* ctx) {
  GLuint id = 0;
  (*kCalls[static_cast<int>(K)].gen)(1, &id);
  reset(ctx, id);
}

template class GlName<GlKind::texture>;
template class GlName<GlKind::framebuffer>;
template class GlName<GlKind::renderbuffer>;
template class GlName<GlKind::vertex_array>;
template class GlName<GlKind::buffer>;

}  // namespace brushwork
