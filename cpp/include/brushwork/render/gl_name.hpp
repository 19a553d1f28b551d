// GL object names as small owners: each deletes its object (glDelete*) when it goes or takes
// another, in the context that made it, while that context is open (closing a context takes its
// objects along, so a name outliving it is only forgotten).
#pragma once

namespace brushwork {

class RenderContext;

enum class GlKind { texture, framebuffer, renderbuffer, vertex_array, buffer };

template <GlKind K>
class GlName {
 public:
  GlName() = default;
  ~GlName() { reset(); }
  GlName(const GlName&) = delete;
  GlName& operator=(const GlName&) = delete;

  operator unsigned() const { return id_; }  // the name, for the GL calls (0: none)
  // delete the object held, then hold `id`, made in `ctx` (current)
  void reset(const RenderContext* ctx = nullptr, unsigned id = 0);
  // delete the object held, then hold a new one made in `ctx` (current) by glGen*
  void generate(const RenderContext* ctx);

 private:
  const RenderContext* ctx_ = nullptr;
  unsigned id_ = 0;
};

using GlTexture = GlName<GlKind::texture>;
using GlFramebuffer = GlName<GlKind::framebuffer>;
using GlRenderbuffer = GlName<GlKind::renderbuffer>;
using GlVertexArray = GlName<GlKind::vertex_array>;
using GlBuffer = GlName<GlKind::buffer>;

}  // namespace brushwork
