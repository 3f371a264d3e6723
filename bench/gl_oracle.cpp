#include "gl_oracle.hpp"

#include "facet/renderer.hpp"

#define GL_GLEXT_PROTOTYPES 1
#include <EGL/egl.h>
#include <EGL/eglext.h>
#include <GL/glcorearb.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <iomanip>
#include <mutex>
#include <sstream>

namespace facet::bench {

namespace {

const char* egl_error_name(EGLint e) {
    switch (e) {
        case EGL_SUCCESS: return "EGL_SUCCESS";
        case EGL_NOT_INITIALIZED: return "EGL_NOT_INITIALIZED";
        case EGL_BAD_ACCESS: return "EGL_BAD_ACCESS";
        case EGL_BAD_ALLOC: return "EGL_BAD_ALLOC";
        case EGL_BAD_ATTRIBUTE: return "EGL_BAD_ATTRIBUTE";
        case EGL_BAD_CONFIG: return "EGL_BAD_CONFIG";
        case EGL_BAD_CONTEXT: return "EGL_BAD_CONTEXT";
        case EGL_BAD_CURRENT_SURFACE: return "EGL_BAD_CURRENT_SURFACE";
        case EGL_BAD_DISPLAY: return "EGL_BAD_DISPLAY";
        case EGL_BAD_MATCH: return "EGL_BAD_MATCH";
        case EGL_BAD_NATIVE_PIXMAP: return "EGL_BAD_NATIVE_PIXMAP";
        case EGL_BAD_NATIVE_WINDOW: return "EGL_BAD_NATIVE_WINDOW";
        case EGL_BAD_PARAMETER: return "EGL_BAD_PARAMETER";
        case EGL_BAD_SURFACE: return "EGL_BAD_SURFACE";
        case EGL_CONTEXT_LOST: return "EGL_CONTEXT_LOST";
        default: return "unknown EGL error";
    }
}

Error egl_failure(const std::string& call) {
    char code[16];
    const EGLint e = eglGetError();
    std::snprintf(code, sizeof code, "0x%04x", static_cast<unsigned>(e));
    return Error{ErrorCode::unsupported, std::string(k_unavailable_prefix) + call + " failed: " + egl_error_name(e) + " (" + code + ")"};
}

bool has_word(const char* list, const char* word) {
    if (!list) return false;
    const std::size_t n = std::strlen(word);
    for (const char* p = list; (p = std::strstr(p, word)) != nullptr; p += n)
        if ((p == list || p[-1] == ' ') && (p[n] == ' ' || p[n] == '\0')) return true;
    return false;
}

// LP_NUM_THREADS is read when the driver's screen is created; remember what this process used.
std::mutex g_env_mutex;
bool g_driver_loaded = false;
int g_llvmpipe_threads = -1;

const char* k_vertex_shader = R"(#version 330 core
layout(location = 0) in vec3 a_position;
layout(location = 1) in vec3 a_normal;
uniform mat4 u_clip_from_object;
uniform mat3 u_normal_to_world;
out vec3 v_normal;
void main() {
    v_normal = u_normal_to_world * a_normal;
    gl_Position = u_clip_from_object * vec4(a_position, 1.0);
}
)";

// facet's lambert mode: albedo 0.8, ambient 0.15, diffuse 0.85, one white light toward the eye.
// The normal and instance outputs go to attachments only with passes (resize); otherwise there is
// one draw buffer and GL discards them.
const char* k_fragment_shader = R"(#version 330 core
in vec3 v_normal;
uniform vec3 u_light;
uniform uint u_instance;
layout(location = 0) out vec4 o_colour;
layout(location = 1) out vec4 o_normal;
layout(location = 2) out uint o_instance;
void main() {
    vec3 n = normalize(v_normal);
    float k = max(dot(n, u_light), 0.0);
    float c = 0.8 * (0.15 + 0.85 * k);
    o_colour = vec4(c, c, c, 1.0);
    o_normal = vec4(n, 0.0);
    o_instance = u_instance;
}
)";

}  // namespace

struct GlOracle::Impl {
    EGLDisplay display = EGL_NO_DISPLAY;
    EGLContext context = EGL_NO_CONTEXT;
    GLuint program = 0;
    GLint u_clip_from_object = -1, u_normal_to_world = -1, u_light = -1, u_instance = -1;
    GLuint fbo = 0, colour_rb = 0, depth_rb = 0, normal_rb = 0, instance_rb = 0;
    int width = 0, height = 0;
    bool passes = false;
    float point_size = 1, line_width = 1;
    bool line_blend = false;
    struct Object {
        GLuint vao = 0, vbo = 0, ibo = 0;
        GLsizei index_count = 0, point_count = 0, line_count = 0;  // in the index buffer in this order
        Mat4 model;
        std::uint32_t instance = 0;  // the scene object's index + 1
    };
    std::vector<Object> objects;

    void release_objects() {
        for (Object& o : objects) {
            glDeleteVertexArrays(1, &o.vao);
            glDeleteBuffers(1, &o.vbo);
            glDeleteBuffers(1, &o.ibo);
        }
        objects.clear();
    }
    void release_framebuffer() {
        if (fbo) glDeleteFramebuffers(1, &fbo);
        if (colour_rb) glDeleteRenderbuffers(1, &colour_rb);
        if (depth_rb) glDeleteRenderbuffers(1, &depth_rb);
        if (normal_rb) glDeleteRenderbuffers(1, &normal_rb);
        if (instance_rb) glDeleteRenderbuffers(1, &instance_rb);
        fbo = colour_rb = depth_rb = normal_rb = instance_rb = 0;
        width = height = 0;
        passes = false;
    }
};

namespace {

Result<GLuint> compile(GLenum kind, const char* source) {
    const GLuint s = glCreateShader(kind);
    glShaderSource(s, 1, &source, nullptr);
    glCompileShader(s);
    GLint ok = 0;
    glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
    if (!ok) {
        char log[2048] = {};
        glGetShaderInfoLog(s, sizeof log, nullptr, log);
        glDeleteShader(s);
        return Error{ErrorCode::unsupported, std::string("llvmpipe oracle: shader does not compile: ") + log};
    }
    return s;
}

}  // namespace

Result<std::unique_ptr<GlOracle>> GlOracle::create(const GlOracleOptions& options) {
    {
        std::lock_guard<std::mutex> lock(g_env_mutex);
        if (options.llvmpipe_threads >= 0) {
            if (g_driver_loaded && g_llvmpipe_threads != options.llvmpipe_threads)
                return Error{ErrorCode::invalid_argument,
                             "llvmpipe oracle: LP_NUM_THREADS is read once per process (it was " +
                                 std::to_string(g_llvmpipe_threads) + "); use a child process for " +
                                 std::to_string(options.llvmpipe_threads)};
            setenv("LP_NUM_THREADS", std::to_string(options.llvmpipe_threads).c_str(), 1);
        }
        if (!g_driver_loaded) {
            const char* lp = std::getenv("LP_NUM_THREADS");
            g_llvmpipe_threads = lp ? std::atoi(lp) : -1;
        }
        setenv("GALLIUM_DRIVER", "llvmpipe", 1);
    }

    std::unique_ptr<GlOracle> oracle(new GlOracle());
    oracle->impl_ = std::make_unique<Impl>();
    Impl& g = *oracle->impl_;

    const char* client_ext = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
    if (!has_word(client_ext, "EGL_MESA_platform_surfaceless"))
        return Error{ErrorCode::unsupported,
                     std::string(k_unavailable_prefix) + "EGL has no EGL_MESA_platform_surfaceless (client extensions: " +
                         std::string(client_ext ? client_ext : "none") + "); install libegl-mesa0"};
    auto get_platform_display =
        reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(eglGetProcAddress("eglGetPlatformDisplayEXT"));
    if (!get_platform_display) return egl_failure("eglGetProcAddress(eglGetPlatformDisplayEXT)");
    g.display = get_platform_display(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
    if (g.display == EGL_NO_DISPLAY) return egl_failure("eglGetPlatformDisplayEXT(EGL_PLATFORM_SURFACELESS_MESA)");
    EGLint major = 0, minor = 0;
    if (!eglInitialize(g.display, &major, &minor)) {
        g.display = EGL_NO_DISPLAY;
        return egl_failure("eglInitialize(surfaceless)");
    }
    {
        std::lock_guard<std::mutex> lock(g_env_mutex);
        g_driver_loaded = true;
    }
    if (!eglBindAPI(EGL_OPENGL_API)) return egl_failure("eglBindAPI(EGL_OPENGL_API)");

    EGLConfig config = nullptr;  // EGL_NO_CONFIG_KHR
    if (!has_word(eglQueryString(g.display, EGL_EXTENSIONS), "EGL_KHR_no_config_context")) {
        const EGLint want[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_NONE};
        EGLint n = 0;
        if (!eglChooseConfig(g.display, want, &config, 1, &n) || n < 1) return egl_failure("eglChooseConfig(EGL_OPENGL_BIT)");
    }
    const EGLint context_attribs[] = {EGL_CONTEXT_MAJOR_VERSION, 3, EGL_CONTEXT_MINOR_VERSION, 3,
                                      EGL_CONTEXT_OPENGL_PROFILE_MASK, EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT, EGL_NONE};
    g.context = eglCreateContext(g.display, config, EGL_NO_CONTEXT, context_attribs);
    if (g.context == EGL_NO_CONTEXT) return egl_failure("eglCreateContext(OpenGL 3.3 core)");
    if (!eglMakeCurrent(g.display, EGL_NO_SURFACE, EGL_NO_SURFACE, g.context))
        return egl_failure("eglMakeCurrent(surfaceless)");

    const std::string renderer = oracle->renderer();
    if (renderer.find("llvmpipe") == std::string::npos)
        return Error{ErrorCode::unsupported, std::string(k_unavailable_prefix) + "the GL renderer is '" + renderer + "', not llvmpipe"};

    // Depth in [0, 1] as facet's _zo projection: core in 4.5, or ARB_clip_control.
    GLint gl_major = 0, gl_minor = 0;
    glGetIntegerv(GL_MAJOR_VERSION, &gl_major);
    glGetIntegerv(GL_MINOR_VERSION, &gl_minor);
    bool clip_control = gl_major > 4 || (gl_major == 4 && gl_minor >= 5);
    GLint extension_count = 0;
    glGetIntegerv(GL_NUM_EXTENSIONS, &extension_count);
    for (GLint i = 0; i < extension_count && !clip_control; ++i)
        clip_control = std::strcmp(reinterpret_cast<const char*>(glGetStringi(GL_EXTENSIONS, i)), "GL_ARB_clip_control") == 0;
    oracle->clip_control_ = clip_control;
    if (clip_control) glClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE);

    auto vs = compile(GL_VERTEX_SHADER, k_vertex_shader);
    if (!vs) return vs.error();
    auto fs = compile(GL_FRAGMENT_SHADER, k_fragment_shader);
    if (!fs) return fs.error();
    g.program = glCreateProgram();
    glAttachShader(g.program, *vs);
    glAttachShader(g.program, *fs);
    glLinkProgram(g.program);
    glDeleteShader(*vs);
    glDeleteShader(*fs);
    GLint linked = 0;
    glGetProgramiv(g.program, GL_LINK_STATUS, &linked);
    if (!linked) return Error{ErrorCode::unsupported, "llvmpipe oracle: the shader program does not link"};
    g.u_clip_from_object = glGetUniformLocation(g.program, "u_clip_from_object");
    g.u_normal_to_world = glGetUniformLocation(g.program, "u_normal_to_world");
    g.u_light = glGetUniformLocation(g.program, "u_light");
    g.u_instance = glGetUniformLocation(g.program, "u_instance");

    // facet's lambert state: no culling, depth test less with writes, no blending.
    glDisable(GL_CULL_FACE);
    glDisable(GL_BLEND);
    glDisable(GL_DITHER);
    glDisable(GL_MULTISAMPLE);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glDepthMask(GL_TRUE);
    glDepthRange(0.0, 1.0);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    if (const std::string e = oracle->gl_error(); !e.empty())
        return Error{ErrorCode::unsupported, "llvmpipe oracle: GL error while setting up: " + e};
    return oracle;
}

GlOracle::~GlOracle() {
    if (!impl_) return;
    Impl& g = *impl_;
    if (g.context != EGL_NO_CONTEXT) {
        eglMakeCurrent(g.display, EGL_NO_SURFACE, EGL_NO_SURFACE, g.context);
        g.release_objects();
        g.release_framebuffer();
        if (g.program) glDeleteProgram(g.program);
        eglMakeCurrent(g.display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
        eglDestroyContext(g.display, g.context);
    }
    if (g.display != EGL_NO_DISPLAY) eglTerminate(g.display);
}

std::string GlOracle::renderer() const {
    const auto* s = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
    return s ? s : "";
}

std::string GlOracle::version() const {
    const auto* s = reinterpret_cast<const char*>(glGetString(GL_VERSION));
    return s ? s : "";
}

int GlOracle::llvmpipe_threads() const {
    std::lock_guard<std::mutex> lock(g_env_mutex);
    return g_llvmpipe_threads;
}

std::string GlOracle::gl_error() {
    std::string out;
    for (GLenum e; (e = glGetError()) != GL_NO_ERROR;) {
        char buf[16];
        std::snprintf(buf, sizeof buf, "0x%04x", e);
        out += out.empty() ? buf : std::string(" ") + buf;
    }
    return out;
}

Status GlOracle::load(const Scene& scene) {
    Impl& g = *impl_;
    g.release_objects();
    for (std::size_t index = 0; index < scene.objects.size(); ++index) {
        const SceneObject& so = scene.objects[index];
        const Mesh& m = so.mesh;
        if (m.indices.empty() && m.points.empty() && m.lines.empty()) continue;
        if (m.normals.size() != m.positions.size())
            return Error{ErrorCode::invalid_argument, "llvmpipe oracle: an object has no normals (facet would shade it flat)"};
        std::vector<float> interleaved(m.positions.size() * 6);
        for (std::size_t i = 0; i < m.positions.size(); ++i) {
            float* v = interleaved.data() + i * 6;
            v[0] = m.positions[i].x, v[1] = m.positions[i].y, v[2] = m.positions[i].z;
            v[3] = m.normals[i].x, v[4] = m.normals[i].y, v[5] = m.normals[i].z;
        }
        Impl::Object o;
        o.model = so.model;
        o.instance = static_cast<std::uint32_t>(index + 1);
        o.index_count = static_cast<GLsizei>(m.indices.size() / 3 * 3);
        o.point_count = static_cast<GLsizei>(m.points.size());
        o.line_count = static_cast<GLsizei>(m.lines.size() / 2 * 2);
        std::vector<std::uint32_t> all(m.indices.begin(), m.indices.begin() + o.index_count);
        all.insert(all.end(), m.points.begin(), m.points.end());
        all.insert(all.end(), m.lines.begin(), m.lines.begin() + o.line_count);
        glGenVertexArrays(1, &o.vao);
        glBindVertexArray(o.vao);
        glGenBuffers(1, &o.vbo);
        glBindBuffer(GL_ARRAY_BUFFER, o.vbo);
        glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(interleaved.size() * sizeof(float)), interleaved.data(),
                     GL_STATIC_DRAW);
        glEnableVertexAttribArray(0);
        glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 6 * sizeof(float), nullptr);
        glEnableVertexAttribArray(1);
        glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, 6 * sizeof(float), reinterpret_cast<const void*>(3 * sizeof(float)));
        glGenBuffers(1, &o.ibo);
        glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, o.ibo);
        glBufferData(GL_ELEMENT_ARRAY_BUFFER, static_cast<GLsizeiptr>(all.size() * sizeof(std::uint32_t)), all.data(),
                     GL_STATIC_DRAW);
        glBindVertexArray(0);
        g.objects.push_back(o);
    }
    if (const std::string e = gl_error(); !e.empty())
        return Error{ErrorCode::unsupported, "llvmpipe oracle: GL error while uploading meshes: " + e};
    return Ok{};
}

Status GlOracle::resize(int width, int height, bool passes) {
    Impl& g = *impl_;
    if (width < 1 || height < 1) return Error{ErrorCode::invalid_argument, "llvmpipe oracle: empty target size"};
    if (g.fbo && g.width == width && g.height == height && g.passes == passes) return Ok{};
    g.release_framebuffer();
    glGenFramebuffers(1, &g.fbo);
    glBindFramebuffer(GL_FRAMEBUFFER, g.fbo);
    // A renderbuffer of `format` at the size, attached at `attachment`.
    auto attach = [&](GLuint& rb, GLenum format, GLenum attachment) {
        glGenRenderbuffers(1, &rb);
        glBindRenderbuffer(GL_RENDERBUFFER, rb);
        glRenderbufferStorage(GL_RENDERBUFFER, format, width, height);
        glFramebufferRenderbuffer(GL_FRAMEBUFFER, attachment, GL_RENDERBUFFER, rb);
    };
    attach(g.colour_rb, GL_RGBA8, GL_COLOR_ATTACHMENT0);
    attach(g.depth_rb, GL_DEPTH_COMPONENT32F, GL_DEPTH_ATTACHMENT);
    if (passes) {
        attach(g.normal_rb, GL_RGBA32F, GL_COLOR_ATTACHMENT1);
        attach(g.instance_rb, GL_R32UI, GL_COLOR_ATTACHMENT2);
    }
    const GLenum status = glCheckFramebufferStatus(GL_FRAMEBUFFER);
    if (status != GL_FRAMEBUFFER_COMPLETE) {
        char buf[16];
        std::snprintf(buf, sizeof buf, "0x%04x", status);
        g.release_framebuffer();
        return Error{ErrorCode::unsupported, std::string("llvmpipe oracle: framebuffer incomplete: ") + buf};
    }
    const GLenum draw_buffers[] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1, GL_COLOR_ATTACHMENT2};
    glDrawBuffers(passes ? 3 : 1, draw_buffers);
    glReadBuffer(GL_COLOR_ATTACHMENT0);
    glViewport(0, 0, width, height);
    g.width = width;
    g.height = height;
    g.passes = passes;
    if (const std::string e = gl_error(); !e.empty())
        return Error{ErrorCode::unsupported, "llvmpipe oracle: GL error while making the framebuffer: " + e};
    return Ok{};
}

void GlOracle::draw(const Camera& camera, Vec4 background) {
    Impl& g = *impl_;
    const float aspect = static_cast<float>(g.width) / static_cast<float>(g.height);
    // As render_scene: clip_from_world = projection * view, then * model per object.
    Mat4 clip_from_world = camera.projection(aspect) * camera.view();
    if (!clip_control_) {
        // GL's default clip z is [-w, w]: z' = 2 z - w maps facet's [0, w] onto it, and the window
        // depth (z'/w + 1) / 2 is then z / w again.
        Mat4 remap = Mat4::identity();
        remap(2, 2) = 2;
        remap(2, 3) = -1;
        clip_from_world = remap * clip_from_world;
    }
    // As uniforms_for: the light is the unit vector from the target to the eye.
    const Vec3 light = -camera_basis(camera.target - camera.position, camera.up, camera.handedness).forward;

    glBindFramebuffer(GL_FRAMEBUFFER, g.fbo);
    if (g.passes) {
        // glClear leaves integer attachments undefined: each buffer is cleared by its kind.
        const GLfloat colour[] = {background.x, background.y, background.z, background.w}, none[] = {0, 0, 0, 0}, far = 1;
        const GLuint no_instance[] = {0, 0, 0, 0};
        glClearBufferfv(GL_COLOR, 0, colour);
        glClearBufferfv(GL_COLOR, 1, none);
        glClearBufferuiv(GL_COLOR, 2, no_instance);
        glClearBufferfv(GL_DEPTH, 0, &far);
    } else {
        glClearColor(background.x, background.y, background.z, background.w);
        glClearDepth(1.0);
        glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    }
    glUseProgram(g.program);
    glUniform3f(g.u_light, light.x, light.y, light.z);
    for (const Impl::Object& o : g.objects) {
        const Mat4 clip_from_object = clip_from_world * o.model;
        const Mat3 normal_to_world = normal_matrix(o.model);
        float m4[16], m3[9];
        for (int c = 0; c < 4; ++c)
            for (int r = 0; r < 4; ++r) m4[c * 4 + r] = clip_from_object(r, c);
        for (int c = 0; c < 3; ++c)
            for (int r = 0; r < 3; ++r) m3[c * 3 + r] = normal_to_world(r, c);
        glUniformMatrix4fv(g.u_clip_from_object, 1, GL_FALSE, m4);  // column-major, as facet stores it
        glUniformMatrix3fv(g.u_normal_to_world, 1, GL_FALSE, m3);
        glUniform1ui(g.u_instance, o.instance);
        glBindVertexArray(o.vao);
        if (o.index_count) glDrawElements(GL_TRIANGLES, o.index_count, GL_UNSIGNED_INT, nullptr);
        const auto offset = [](GLsizei n) { return reinterpret_cast<const void*>(static_cast<std::uintptr_t>(n) * sizeof(std::uint32_t)); };
        if (o.point_count) {
            glPointSize(g.point_size);
            glDrawElements(GL_POINTS, o.point_count, GL_UNSIGNED_INT, offset(o.index_count));
        }
        if (o.line_count) {
            glLineWidth(g.line_width);
            // Blended without depth writes, as facet's anti-aliased lines; GL_LINE_SMOOTH itself is left
            // out: llvmpipe (Mesa 22.3, LLVM 15) crashes compiling the oracle's shader with it.
            if (g.line_blend) {
                glEnable(GL_BLEND);
                glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
                glDepthMask(GL_FALSE);
            }
            glDrawElements(GL_LINES, o.line_count, GL_UNSIGNED_INT, offset(o.index_count + o.point_count));
            if (g.line_blend) {
                glDisable(GL_BLEND);
                glDepthMask(GL_TRUE);
            }
        }
    }
    glBindVertexArray(0);
}

void GlOracle::set_primitive_style(float point_size, float line_width, bool line_blend) {
    impl_->point_size = point_size;
    impl_->line_width = line_width;
    impl_->line_blend = line_blend;
}

void GlOracle::finish() { glFinish(); }

GlFrame GlOracle::read() {
    Impl& g = *impl_;
    GlFrame f;
    f.width = g.width;
    f.height = g.height;
    const std::size_t n = static_cast<std::size_t>(g.width) * g.height;
    std::vector<Rgba8> colour(n);
    std::vector<float> depth(n);
    glBindFramebuffer(GL_FRAMEBUFFER, g.fbo);
    glReadPixels(0, 0, g.width, g.height, GL_RGBA, GL_UNSIGNED_BYTE, colour.data());
    glReadPixels(0, 0, g.width, g.height, GL_DEPTH_COMPONENT, GL_FLOAT, depth.data());
    // GL's row 0 is the bottom of the picture; facet's is the top.
    f.colour.resize(n);
    f.depth.resize(n);
    std::vector<float> normal;
    std::vector<std::uint32_t> instance;
    if (g.passes) {
        normal.resize(n * 4);
        instance.resize(n);
        glReadBuffer(GL_COLOR_ATTACHMENT1);
        glReadPixels(0, 0, g.width, g.height, GL_RGBA, GL_FLOAT, normal.data());
        glReadBuffer(GL_COLOR_ATTACHMENT2);
        glReadPixels(0, 0, g.width, g.height, GL_RED_INTEGER, GL_UNSIGNED_INT, instance.data());
        glReadBuffer(GL_COLOR_ATTACHMENT0);
        f.normal.resize(n);
        f.instance.resize(n);
    }
    for (int y = 0; y < g.height; ++y) {
        const std::size_t src = static_cast<std::size_t>(g.height - 1 - y) * g.width, dst = static_cast<std::size_t>(y) * g.width;
        std::copy_n(colour.begin() + static_cast<std::ptrdiff_t>(src), g.width, f.colour.begin() + static_cast<std::ptrdiff_t>(dst));
        std::copy_n(depth.begin() + static_cast<std::ptrdiff_t>(src), g.width, f.depth.begin() + static_cast<std::ptrdiff_t>(dst));
        if (!g.passes) continue;
        std::copy_n(instance.begin() + static_cast<std::ptrdiff_t>(src), g.width, f.instance.begin() + static_cast<std::ptrdiff_t>(dst));
        for (int x = 0; x < g.width; ++x) {
            const float* v = &normal[(src + static_cast<std::size_t>(x)) * 4];
            f.normal[dst + static_cast<std::size_t>(x)] = {v[0], v[1], v[2]};
        }
    }
    return f;
}

Result<GlFrame> GlOracle::render(const Scene& scene, const Camera& camera, int width, int height, Vec4 background) {
    if (Status s = load(scene); !s) return s.error();
    if (Status s = resize(width, height); !s) return s.error();
    draw(camera, background);
    GlFrame f = read();
    if (const std::string e = gl_error(); !e.empty())
        return Error{ErrorCode::unsupported, "llvmpipe oracle: GL error while drawing: " + e};
    return f;
}

Agreement compare(const Rgba8* facet_colour, const float* facet_depth, const GlFrame& gl) {
    Agreement a;
    a.pixels = static_cast<std::size_t>(gl.width) * gl.height;
    double depth_sum = 0, colour_sum = 0;
    for (std::size_t i = 0; i < a.pixels; ++i) {
        const bool f = facet_depth[i] < 1.0f, o = gl.depth[i] < 1.0f;
        if (!f && !o) continue;
        ++a.covered_union;
        if (f && !o) ++a.only_facet;
        if (o && !f) ++a.only_gl;
        if (!(f && o)) continue;
        ++a.covered_both;
        const double dd = std::fabs(static_cast<double>(facet_depth[i]) - gl.depth[i]);
        a.max_depth_diff = std::max(a.max_depth_diff, dd);
        depth_sum += dd;
        if (dd > 1e-4) ++a.depth_over_1e4;
        const Rgba8 p = facet_colour[i], q = gl.colour[i];
        const int cd = std::max({std::abs(p.r - q.r), std::abs(p.g - q.g), std::abs(p.b - q.b), std::abs(p.a - q.a)});
        a.max_colour_diff = std::max(a.max_colour_diff, cd);
        colour_sum += cd;
        if (cd > 2) ++a.colour_over_2;
    }
    if (a.covered_union) a.coverage_agreement = static_cast<double>(a.covered_both) / static_cast<double>(a.covered_union);
    if (a.covered_both) {
        a.mean_depth_diff = depth_sum / static_cast<double>(a.covered_both);
        a.mean_colour_diff = colour_sum / static_cast<double>(a.covered_both);
    }
    return a;
}

std::string describe(const Agreement& a) {
    std::ostringstream s;
    s.precision(6);
    s << "coverage " << a.covered_both << "/" << a.covered_union << " = " << std::fixed << 100.0 * a.coverage_agreement
      << "% (only facet " << a.only_facet << ", only llvmpipe " << a.only_gl << "); depth max " << std::scientific
      << a.max_depth_diff << " mean " << a.mean_depth_diff << " (>1e-4: " << a.depth_over_1e4 << "); colour max "
      << a.max_colour_diff << " mean " << std::fixed << std::setprecision(4) << a.mean_colour_diff << " (>2: " << a.colour_over_2 << ")";
    return s.str();
}


DepthOutliers explain_depth_outliers(const Scene& scene, const Camera& camera, const Framebuffer& facet,
                                     const GlFrame& gl, double tolerance) {
    DepthOutliers out;
    const int w = facet.width(), h = facet.height();
    if (gl.width != w || gl.height != h) {
        out.unexplained = "the frames differ in size";
        return out;
    }
    std::vector<std::size_t> pixels;
    for (std::size_t i = 0; i < static_cast<std::size_t>(w) * h; ++i)
        if (facet.depth_data()[i] < 1 && gl.depth[i] < 1 && std::fabs(facet.depth_data()[i] - gl.depth[i]) > tolerance)
            pixels.push_back(i);
    out.total = pixels.size();
    if (pixels.empty()) return out;

    // Which triangle facet drew at each pixel: the scene again, every triangle with its own three
    // vertices carrying its index, written as 24 bits of colour. Same clip positions, same order,
    // so the same depths.
    const float aspect = static_cast<float>(w) / static_cast<float>(h);
    const Mat4 clip_from_world = camera.projection(aspect) * camera.view();
    Framebuffer ids(w, h);
    ids.clear({1, 1, 1, 1});
    Renderer renderer(RendererConfig{.threads = 1});
    std::vector<std::pair<std::size_t, std::size_t>> owner;  // triangle id -> (object, triangle)
    for (std::size_t o = 0; o < scene.objects.size(); ++o) {
        const Mesh& m = scene.objects[o].mesh;
        const Mat4 clip_from_object = clip_from_world * scene.objects[o].model;
        const auto first = static_cast<std::uint32_t>(owner.size());
        for (std::size_t t = 0; t < m.indices.size() / 3; ++t) owner.push_back({o, t});
        auto shader = make_shader<1>(
            [&](std::uint32_t i, Varyings<1>& v) {
                v[0] = static_cast<float>(first + i / 3);
                return clip_from_object * Vec4(m.positions[m.indices[i]], 1);
            },
            [](const FragmentIn<1>& in) {
                const auto id = static_cast<std::uint32_t>(in.v[0] + 0.5f);
                return Vec4{static_cast<float>(id & 255) / 255, static_cast<float>((id >> 8) & 255) / 255,
                            static_cast<float>((id >> 16) & 255) / 255, 1};
            });
        DrawState ds;
        ds.cull = CullMode::none;
        renderer.draw(ids, ds, DrawInput{static_cast<std::uint32_t>(m.indices.size() / 3 * 3), {}}, shader);
    }

    for (std::size_t i : pixels) {
        const int px = static_cast<int>(i % static_cast<std::size_t>(w)), py = static_cast<int>(i / static_cast<std::size_t>(w));
        const Rgba8 c = ids.colour_data()[i];
        const std::uint32_t id = static_cast<std::uint32_t>(c.r) | (static_cast<std::uint32_t>(c.g) << 8) |
                                 (static_cast<std::uint32_t>(c.b) << 16);
        std::ostringstream why;
        why.precision(7);
        why << "pixel (" << px << ", " << py << ") facet " << facet.depth_data()[i] << " llvmpipe " << gl.depth[i];
        if (id >= owner.size() || ids.depth_data()[i] != facet.depth_data()[i]) {
            if (out.unexplained.size() < 1000) out.unexplained += why.str() + ": not one triangle's depth; ";
            continue;
        }
        const auto [o, t] = owner[id];
        const Mesh& m = scene.objects[o].mesh;
        const Mat4 clip_from_object = clip_from_world * scene.objects[o].model;
        // facet's projection (divide by w, viewport with y down), snapped to 1/256 pixel or not.
        double x[3], y[3], sx[3], sy[3], z[3];
        bool inside = true;  // not clipped: the plane is the triangle's own
        for (int k = 0; k < 3; ++k) {
            const Vec4 p = clip_from_object * Vec4(m.positions[m.indices[t * 3 + static_cast<std::size_t>(k)]], 1);
            inside = inside && p.w > 0 && p.z >= 0 && p.z <= p.w;
            const float q = 1.0f / p.w;
            const float fx = (p.x * q + 1.0f) * (static_cast<float>(w) * 0.5f);
            const float fy = (1.0f - p.y * q) * (static_cast<float>(h) * 0.5f);
            x[k] = fx, y[k] = fy, z[k] = p.z * q;
            sx[k] = static_cast<double>(std::lrint(fx * 256.0f)) / 256;
            sy[k] = static_cast<double>(std::lrint(fy * 256.0f)) / 256;
        }
        auto plane_at = [&](const double(&vx)[3], const double(&vy)[3]) {
            const double area = (vx[1] - vx[0]) * (vy[2] - vy[0]) - (vx[2] - vx[0]) * (vy[1] - vy[0]);
            const double d1 = z[1] - z[0], d2 = z[2] - z[0];
            const double dzdx = (d1 * (vy[2] - vy[0]) - d2 * (vy[1] - vy[0])) / area;
            const double dzdy = (d2 * (vx[1] - vx[0]) - d1 * (vx[2] - vx[0])) / area;
            return z[0] + dzdx * (px + 0.5 - vx[0]) + dzdy * (py + 0.5 - vy[0]);
        };
        const double snapped = plane_at(sx, sy), unsnapped = plane_at(x, y);
        const double area_px = 0.5 * std::fabs((x[1] - x[0]) * (y[2] - y[0]) - (x[2] - x[0]) * (y[1] - y[0]));
        why << ": object " << o << " triangle " << t << " (" << area_px << " px^2), plane through snapped vertices "
            << snapped << ", through unsnapped " << unsnapped;
        // facet: exactly its snapped plane (its planes are set up in double from the snapped integer
        // coordinates). llvmpipe: the unsnapped plane, up to its own float set-up, whose error grows as
        // the sliver gets thinner; it must sit at the unsnapped end of the gap, within a quarter of it.
        const double gap = std::fabs(snapped - unsnapped);
        if (inside && std::fabs(facet.depth_data()[i] - snapped) <= 1e-5 &&
            std::fabs(gl.depth[i] - unsnapped) <= 1e-5 + 0.25 * gap) {
            ++out.explained;
            if (out.explained_details.size() < 50) out.explained_details.push_back(why.str());
        } else if (out.unexplained.size() < 1000) {
            out.unexplained += why.str() + "; ";
        }
    }
    return out;
}

}  // namespace facet::bench
