#include "editor/viewport/scene_view.h"

#include <QGuiApplication>
#include <QKeyEvent>
#include <QMouseEvent>
#include <QOpenGLContext>
#include <QOpenGLFunctions>
#include <QOpenGLShaderProgram>
#include <QPainter>
#include <QWheelEvent>

#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <cmath>
#include <cstddef>

// Shaders live in the editor library's resources (resources/shaders/shaders.qrc); a static
// library registers them explicitly.
static void initShaderResources() { Q_INIT_RESOURCE(shaders); }

namespace mlod {

namespace {

struct GpuVertex {
  float position[3];
  float normal[3];
  std::uint32_t joints[4];
  float weights[4];
};

} // namespace

bool sceneViewSupported(QString* out_reason) {
  const QString platform = QGuiApplication::platformName();
  if (platform == QLatin1String("offscreen") || platform == QLatin1String("minimal")) {
    if (out_reason)
      *out_reason = SceneView::tr("The 3D views need OpenGL, which the '%1' platform does not have.").arg(platform);
    return false;
  }
  QOpenGLContext probe;
  probe.setFormat(QSurfaceFormat::defaultFormat());
  if (!probe.create()) {
    if (out_reason)
      *out_reason = SceneView::tr("The 3D views need OpenGL 3.3, and no OpenGL context could be created here.");
    return false;
  }
  const QSurfaceFormat format = probe.format();
  if (format.majorVersion() < 3 || (format.majorVersion() == 3 && format.minorVersion() < 3)) {
    if (out_reason)
      *out_reason = SceneView::tr("The 3D views need OpenGL 3.3; this context is %1.%2.")
                        .arg(format.majorVersion())
                        .arg(format.minorVersion());
    return false;
  }
  return true;
}

SceneView::SceneView(QWidget* parent) : QOpenGLWidget(parent) {
  initShaderResources();
  setFocusPolicy(Qt::StrongFocus);
  setMinimumSize(160, 120);
  setToolTip(tr("Orbit: drag (or Alt + left drag) · Pan: middle drag (Alt + middle) · Dolly: wheel or right drag "
                "(Alt + right) · Fly: W A S D Q E with a mouse button held · Frame: F · Play/pause: Space · Click a "
                "joint to select it"));
  setGrid(500.0f, 50.0f);
}

SceneView::~SceneView() {
  releaseGL();
}

void SceneView::releaseGL() {
  if (!m_ready)
    return;
  makeCurrent();
  releaseMeshes(true);
  glDeleteBuffers(1, &m_lineVbo);
  glDeleteVertexArrays(1, &m_lineVao);
  glDeleteTextures(1, &m_paletteTexture);
  glDeleteQueries(1, &m_primitivesQuery);
  m_lineVbo = m_lineVao = m_paletteTexture = m_primitivesQuery = 0;
  m_skinned.reset();
  m_lineProgram.reset();
  doneCurrent();
  m_ready = false;
  m_textureRows = 0;    // the next context's texture has no storage yet
  m_texelsDirty = true; // and the palettes go up again
}

int SceneView::addMesh(const SkinnedMesh& mesh) {
  auto gpu = std::make_unique<GpuMesh>();
  gpu->source = mesh;
  m_meshes.push_back(std::move(gpu));
  update();
  return static_cast<int>(m_meshes.size()) - 1;
}

void SceneView::clearMeshes() {
  for (const auto& mesh : m_meshes)
    if (mesh->uploaded) {
      m_deadBuffers.insert(m_deadBuffers.end(), {mesh->vbo, mesh->ibo, mesh->instances});
      m_deadArrays.push_back(mesh->vao);
    }
  m_meshes.clear();
  m_batches.clear();
  update();
}

void SceneView::setBatches(std::span<const Batch> batches) {
  m_batches.clear();
  m_instances.clear();
  m_texels.clear();
  for (const Batch& batch : batches) {
    if (batch.mesh < 0 || batch.mesh >= static_cast<int>(m_meshes.size()) || batch.joints <= 0 ||
        batch.instances.empty() || batch.palettes.size() < batch.instances.size() * std::size_t(batch.joints))
      continue;
    BatchInfo info;
    info.mesh = batch.mesh;
    info.joints = batch.joints;
    info.instanceBegin = static_cast<int>(m_instances.size());
    info.instanceCount = static_cast<int>(batch.instances.size());
    info.paletteTexel = static_cast<int>(m_texels.size());
    info.alpha = batch.alpha;
    m_instances.insert(m_instances.end(), batch.instances.begin(), batch.instances.end());
    const std::size_t matrices = batch.instances.size() * std::size_t(batch.joints);
    for (std::size_t m = 0; m < matrices; ++m) {
      const glm::mat4& p = batch.palettes[m];
      for (int r = 0; r < 3; ++r)
        m_texels.emplace_back(p[0][r], p[1][r], p[2][r], p[3][r]);
    }
    m_batches.push_back(info);
  }
  m_texelsDirty = true;
  update();
}

void SceneView::setLines(std::vector<LineVertex> lines, std::vector<LineVertex> points) {
  m_lines = std::move(lines);
  m_points = std::move(points);
  update();
}

void SceneView::setGrid(float extentCm, float stepCm) {
  m_grid.clear();
  const int steps = std::clamp(static_cast<int>(std::ceil(extentCm / stepCm)), 1, 400);
  for (int i = -steps; i <= steps; ++i) {
    const float at = static_cast<float>(i) * stepCm, end = static_cast<float>(steps) * stepCm;
    const glm::vec4 color = i == 0 ? glm::vec4(0.55f, 0.55f, 0.58f, 1.0f) : glm::vec4(0.33f, 0.34f, 0.36f, 1.0f);
    m_grid.push_back({{at, 0.0f, -end}, color});
    m_grid.push_back({{at, 0.0f, end}, color});
    m_grid.push_back({{-end, 0.0f, at}, color});
    m_grid.push_back({{end, 0.0f, at}, color});
  }
  update();
}

glm::mat4 SceneView::viewProjection() const {
  return m_camera.viewProjection(static_cast<float>(width()) / std::max(1, height()));
}

void SceneView::initializeGL() {
  // note: a QOpenGLWidget moved to another window (its dock floats or docks again) gets a
  // new context and calls initializeGL() again; the old context takes its objects with it.
  connect(context(), &QOpenGLContext::aboutToBeDestroyed, this, &SceneView::releaseGL, Qt::UniqueConnection);
  m_glError.clear();
  if (!initializeOpenGLFunctions()) {
    m_glError = tr("OpenGL 3.3 core is not available here (%1).")
                    .arg(QString::fromLatin1(reinterpret_cast<const char*>(context()->functions()->glGetString(GL_VERSION))));
    return;
  }
  m_renderer = QStringLiteral("%1 · OpenGL %2")
                   .arg(QString::fromLatin1(reinterpret_cast<const char*>(glGetString(GL_RENDERER))),
                        QString::fromLatin1(reinterpret_cast<const char*>(glGetString(GL_VERSION))));
  auto build = [this](const QString& vertex, const QString& fragment) {
    auto program = std::make_unique<QOpenGLShaderProgram>();
    if (!program->addShaderFromSourceFile(QOpenGLShader::Vertex, vertex) ||
        !program->addShaderFromSourceFile(QOpenGLShader::Fragment, fragment) || !program->link()) {
      m_glError = tr("Shader error: %1").arg(program->log());
      return std::unique_ptr<QOpenGLShaderProgram>();
    }
    return program;
  };
  m_skinned = build(":/shaders/skinned.vert", ":/shaders/skinned.frag");
  m_lineProgram = build(":/shaders/lines.vert", ":/shaders/lines.frag");
  if (!m_skinned || !m_lineProgram)
    return;
  GLint maxSize = 0;
  glGetIntegerv(GL_MAX_TEXTURE_SIZE, &maxSize);
  m_textureWidth = std::clamp(static_cast<int>(maxSize), 64, 4096);
  glGenTextures(1, &m_paletteTexture);
  glBindTexture(GL_TEXTURE_2D, m_paletteTexture);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  glGenVertexArrays(1, &m_lineVao);
  glGenBuffers(1, &m_lineVbo);
  glBindVertexArray(m_lineVao);
  glBindBuffer(GL_ARRAY_BUFFER, m_lineVbo);
  glEnableVertexAttribArray(0);
  glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, sizeof(LineVertex), reinterpret_cast<void*>(offsetof(LineVertex, position)));
  glEnableVertexAttribArray(1);
  glVertexAttribPointer(1, 4, GL_FLOAT, GL_FALSE, sizeof(LineVertex), reinterpret_cast<void*>(offsetof(LineVertex, color)));
  glBindVertexArray(0);
  glGenQueries(1, &m_primitivesQuery);
  m_texelsDirty = true;
  m_ready = true;
}

void SceneView::upload(GpuMesh& mesh) {
  const SkinnedMesh& source = mesh.source;
  std::vector<GpuVertex> vertices(source.vertexCount());
  for (std::size_t v = 0; v < vertices.size(); ++v) {
    GpuVertex& out = vertices[v];
    const glm::vec3 n = v < source.normals.size() ? source.normals[v] : glm::vec3(0.0f, 1.0f, 0.0f);
    for (int k = 0; k < 3; ++k) {
      out.position[k] = source.positions[v][k];
      out.normal[k] = n[k];
    }
    for (int k = 0; k < 4; ++k) {
      out.joints[k] = source.skinned() ? source.joints[v][k] : 0u;
      out.weights[k] = source.skinned() ? source.weights[v][k] : (k == 0 ? 1.0f : 0.0f);
    }
  }
  glGenVertexArrays(1, &mesh.vao);
  glGenBuffers(1, &mesh.vbo);
  glGenBuffers(1, &mesh.ibo);
  glGenBuffers(1, &mesh.instances);
  glBindVertexArray(mesh.vao);
  glBindBuffer(GL_ARRAY_BUFFER, mesh.vbo);
  glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(vertices.size() * sizeof(GpuVertex)), vertices.data(),
               GL_STATIC_DRAW);
  glEnableVertexAttribArray(0);
  glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, sizeof(GpuVertex), reinterpret_cast<void*>(offsetof(GpuVertex, position)));
  glEnableVertexAttribArray(1);
  glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, sizeof(GpuVertex), reinterpret_cast<void*>(offsetof(GpuVertex, normal)));
  glEnableVertexAttribArray(2);
  glVertexAttribIPointer(2, 4, GL_UNSIGNED_INT, sizeof(GpuVertex), reinterpret_cast<void*>(offsetof(GpuVertex, joints)));
  glEnableVertexAttribArray(3);
  glVertexAttribPointer(3, 4, GL_FLOAT, GL_FALSE, sizeof(GpuVertex), reinterpret_cast<void*>(offsetof(GpuVertex, weights)));
  glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, mesh.ibo);
  glBufferData(GL_ELEMENT_ARRAY_BUFFER, static_cast<GLsizeiptr>(source.indices.size() * sizeof(std::uint32_t)),
               source.indices.data(), GL_STATIC_DRAW);
  glBindBuffer(GL_ARRAY_BUFFER, mesh.instances);
  glEnableVertexAttribArray(4);
  glVertexAttribDivisor(4, 1);
  glEnableVertexAttribArray(5);
  glVertexAttribDivisor(5, 1);
  glBindVertexArray(0);
  mesh.indexCount = static_cast<int>(source.indices.size());
  mesh.uploaded = true;
}

void SceneView::releaseMeshes(bool all) {
  if (all)
    for (const auto& mesh : m_meshes)
      if (mesh->uploaded) {
        m_deadBuffers.insert(m_deadBuffers.end(), {mesh->vbo, mesh->ibo, mesh->instances});
        m_deadArrays.push_back(mesh->vao);
        mesh->uploaded = false;
      }
  if (!m_deadBuffers.empty())
    glDeleteBuffers(static_cast<GLsizei>(m_deadBuffers.size()), m_deadBuffers.data());
  if (!m_deadArrays.empty())
    glDeleteVertexArrays(static_cast<GLsizei>(m_deadArrays.size()), m_deadArrays.data());
  m_deadBuffers.clear();
  m_deadArrays.clear();
}

void SceneView::setWireframe(bool on) {
  m_wireframe = on;
  update();
}

qint64 SceneView::drawBatches(const glm::mat4& viewProjection, bool transparent) {
  qint64 triangles = 0;
  m_skinned->bind();
  glUniformMatrix4fv(m_skinned->uniformLocation("uViewProjection"), 1, GL_FALSE, glm::value_ptr(viewProjection));
  glActiveTexture(GL_TEXTURE0);
  glBindTexture(GL_TEXTURE_2D, m_paletteTexture);
  m_skinned->setUniformValue("uPalettes", 0);
  m_skinned->setUniformValue("uTextureWidth", m_textureWidth);
  const glm::vec3 light = glm::normalize(glm::vec3(0.4f, 0.8f, 0.45f));
  m_skinned->setUniformValue("uLightDirection", light.x, light.y, light.z);
  for (const BatchInfo& batch : m_batches) {
    if ((batch.alpha < 1.0f) != transparent)
      continue;
    GpuMesh& mesh = *m_meshes[static_cast<std::size_t>(batch.mesh)];
    if (!mesh.uploaded)
      upload(mesh);
    m_skinned->setUniformValue("uPaletteBase", batch.paletteTexel);
    m_skinned->setUniformValue("uJointCount", batch.joints);
    m_skinned->setUniformValue("uAlpha", batch.alpha);
    glBindVertexArray(mesh.vao);
    glBindBuffer(GL_ARRAY_BUFFER, mesh.instances);
    glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(std::size_t(batch.instanceCount) * sizeof(Instance)),
                 m_instances.data() + batch.instanceBegin, GL_STREAM_DRAW);
    glVertexAttribPointer(4, 4, GL_FLOAT, GL_FALSE, sizeof(Instance), reinterpret_cast<void*>(offsetof(Instance, position)));
    glVertexAttribPointer(5, 4, GL_FLOAT, GL_FALSE, sizeof(Instance), reinterpret_cast<void*>(offsetof(Instance, tint)));
    glDrawElementsInstanced(GL_TRIANGLES, mesh.indexCount, GL_UNSIGNED_INT, nullptr, batch.instanceCount);
    triangles += qint64(mesh.indexCount / 3) * batch.instanceCount;
  }
  glBindVertexArray(0);
  m_skinned->release();
  return triangles;
}

void SceneView::drawLines(const glm::mat4& viewProjection, bool grid) {
  m_lineProgram->bind();
  glUniformMatrix4fv(m_lineProgram->uniformLocation("uViewProjection"), 1, GL_FALSE, glm::value_ptr(viewProjection));
  m_lineProgram->setUniformValue("uPointSize", 7.0f * static_cast<float>(devicePixelRatioF()));
  glBindVertexArray(m_lineVao);
  glBindBuffer(GL_ARRAY_BUFFER, m_lineVbo);
  auto draw = [this](const std::vector<LineVertex>& vertices, GLenum mode) {
    if (vertices.empty())
      return;
    glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(vertices.size() * sizeof(LineVertex)), vertices.data(),
                 GL_STREAM_DRAW);
    glDrawArrays(mode, 0, static_cast<GLsizei>(vertices.size()));
  };
  if (grid) {
    draw(m_grid, GL_LINES);
  } else { // the overlay shows through the characters
  glDisable(GL_DEPTH_TEST);
  draw(m_lines, GL_LINES);
  glEnable(GL_PROGRAM_POINT_SIZE);
  draw(m_points, GL_POINTS);
  glDisable(GL_PROGRAM_POINT_SIZE);
  glEnable(GL_DEPTH_TEST);
  }
  glBindVertexArray(0);
  m_lineProgram->release();
}

void SceneView::paintGL() {
  ++m_paints;
  if (m_ready) {
    releaseMeshes(false); // what clearMeshes() left for this context
    glClearColor(0.17f, 0.18f, 0.20f, 1.0f);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    glEnable(GL_DEPTH_TEST);
    glDisable(GL_CULL_FACE);
    if (m_texelsDirty && !m_texels.empty()) {
      const int rows = static_cast<int>((m_texels.size() + std::size_t(m_textureWidth) - 1) / std::size_t(m_textureWidth));
      m_texels.resize(std::size_t(rows) * std::size_t(m_textureWidth), glm::vec4(0.0f));
      glBindTexture(GL_TEXTURE_2D, m_paletteTexture);
      if (rows != m_textureRows) {
        glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA32F, m_textureWidth, rows, 0, GL_RGBA, GL_FLOAT, m_texels.data());
        m_textureRows = rows;
      } else {
        glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, m_textureWidth, rows, GL_RGBA, GL_FLOAT, m_texels.data());
      }
      m_texelsDirty = false;
    }
    const glm::mat4 viewProjection = this->viewProjection();
    const float ratio = static_cast<float>(devicePixelRatioF());
    glViewport(0, 0, static_cast<GLsizei>(width() * ratio), static_cast<GLsizei>(height() * ratio));
    drawLines(viewProjection, true); // the grid, then the characters, then the overlay lines
    m_trianglesSubmitted = 0;
    m_trianglesGenerated = -1;
    if (!m_batches.empty()) {
      if (m_wireframe)
        glPolygonMode(GL_FRONT_AND_BACK, GL_LINE);
      glBeginQuery(GL_PRIMITIVES_GENERATED, m_primitivesQuery);
      m_trianglesSubmitted += drawBatches(viewProjection, false);
      // A ghost lies over everything drawn so far (it would hide behind the character it
      // overlays), hiding only its own far side: a depth buffer of its own.
      if (std::any_of(m_batches.begin(), m_batches.end(), [](const BatchInfo& b) { return b.alpha < 1.0f; })) {
        glClear(GL_DEPTH_BUFFER_BIT);
        glEnable(GL_BLEND);
        glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
        m_trianglesSubmitted += drawBatches(viewProjection, true);
        glDisable(GL_BLEND);
      }
      glEndQuery(GL_PRIMITIVES_GENERATED);
      glPolygonMode(GL_FRONT_AND_BACK, GL_FILL);
      // note: waits for the GPU to finish these draws; the viewport draws a few characters,
      // and the count is what tests and --screenshot report as drawn
      GLuint generated = 0;
      glGetQueryObjectuiv(m_primitivesQuery, GL_QUERY_RESULT, &generated);
      m_trianglesGenerated = qint64(generated);
    }
    if (!m_lines.empty() || !m_points.empty())
      drawLines(viewProjection, false);
    glDisable(GL_DEPTH_TEST);
  } else {
    QOpenGLFunctions* f = context()->functions();
    f->glClearColor(0.17f, 0.18f, 0.20f, 1.0f);
    f->glClear(GL_COLOR_BUFFER_BIT);
  }
  QPainter painter(this);
  painter.setPen(QColor(235, 235, 235));
  QFont font = painter.font();
  font.setPointSizeF(9.5);
  painter.setFont(font);
  const QString message = !m_glError.isEmpty() ? m_glError : (m_batches.empty() ? m_message : QString());
  if (!message.isEmpty())
    painter.drawText(rect().adjusted(20, 20, -20, -20), Qt::AlignCenter | Qt::TextWordWrap, message);
  int y = 18;
  for (const QString& line : m_overlay) {
    painter.fillRect(QRect(6, y - 13, painter.fontMetrics().horizontalAdvance(line) + 8, 17), QColor(0, 0, 0, 140));
    painter.drawText(10, y, line);
    y += 18;
  }
}

void SceneView::mousePressEvent(QMouseEvent* event) {
  m_pressPosition = m_lastPosition = event->position().toPoint();
  m_dragButton = event->button();
  m_dragged = false;
  setFocus(Qt::MouseFocusReason);
}

void SceneView::mouseMoveEvent(QMouseEvent* event) {
  if (m_dragButton == Qt::NoButton)
    return;
  const QPoint position = event->position().toPoint();
  const QPoint delta = position - m_lastPosition;
  m_lastPosition = position;
  if ((position - m_pressPosition).manhattanLength() > 3)
    m_dragged = true;
  // Alt + buttons (Maya) and the plain buttons do the same: left orbits, middle pans, right dollies.
  switch (m_dragButton) {
  case Qt::LeftButton:
    m_camera.orbit(float(delta.x()), float(delta.y()));
    break;
  case Qt::MiddleButton:
    m_camera.pan(float(delta.x()), float(delta.y()), float(height()));
    break;
  case Qt::RightButton:
    m_camera.dolly(float(delta.x() - delta.y()) / 40.0f);
    break;
  default:
    return;
  }
  emit cameraChanged();
  update();
}

void SceneView::mouseReleaseEvent(QMouseEvent* event) {
  if (event->button() == m_dragButton && m_dragButton == Qt::LeftButton && !m_dragged)
    emit clicked(event->position().toPoint());
  m_dragButton = Qt::NoButton;
}

void SceneView::wheelEvent(QWheelEvent* event) {
  m_camera.dolly(float(event->angleDelta().y()) / 120.0f);
  emit cameraChanged();
  update();
}

namespace {
bool isFlyKey(int key) {
  return key == Qt::Key_W || key == Qt::Key_A || key == Qt::Key_S || key == Qt::Key_D || key == Qt::Key_Q ||
         key == Qt::Key_E;
}
} // namespace

bool SceneView::event(QEvent* event) {
  // While a mouse button is held the fly keys are the camera's, not a window shortcut's
  // (plain W is the Viewport's wireframe toggle).
  if (event->type() == QEvent::ShortcutOverride && m_dragButton != Qt::NoButton &&
      isFlyKey(static_cast<QKeyEvent*>(event)->key())) {
    event->accept();
    return true;
  }
  return QOpenGLWidget::event(event);
}

void SceneView::keyPressEvent(QKeyEvent* event) {
  if (isFlyKey(event->key()) && m_dragButton == Qt::NoButton) {
    QOpenGLWidget::keyPressEvent(event);
    return;
  }
  const float step = std::max(5.0f, 0.05f * m_camera.distance) * (event->modifiers() & Qt::ShiftModifier ? 5.0f : 1.0f);
  glm::vec3 move(0.0f);
  switch (event->key()) {
  case Qt::Key_F:
    emit frameRequested();
    return;
  case Qt::Key_Space:
    emit togglePlayRequested();
    return;
  case Qt::Key_W: move.z = step; break;
  case Qt::Key_S: move.z = -step; break;
  case Qt::Key_A: move.x = -step; break;
  case Qt::Key_D: move.x = step; break;
  case Qt::Key_E: move.y = step; break;
  case Qt::Key_Q: move.y = -step; break;
  default:
    QOpenGLWidget::keyPressEvent(event);
    return;
  }
  m_camera.fly(move);
  emit cameraChanged();
  update();
}

} // namespace mlod
