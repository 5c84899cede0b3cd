// SPDX-License-Identifier: MIT
// The view's caption (app/studio/scene_view_caption.h) under xvfb-run: its frames equal those of
// vtkCornerAnnotation set up as the studio set it up before (upper left text, size fitted, doubled,
// at most 15), pixel for pixel, for one-line and several-line texts in views from wide to a few
// dozen pixels, as the text, the view's size alone, the style and the DPI change, and in views
// swept across the width and height where the text at size 8 just fits (where the caption's
// shortcut decides); where the caption differs on purpose (tokens such as "<slice>", which
// vtkCornerAnnotation deleted), the frames differ and the caption draws the text as given. In a
// wide view the text is measured at one size only, in a narrow one the size is searched (counted
// by text mappers that VTK's object factory hands the caption in place of the OpenGL ones).
#include <vtkActor2D.h>
#include <vtkCornerAnnotation.h>
#include <vtkNew.h>
#include <vtkObjectFactory.h>
#include <vtkOpenGLTextMapper.h>
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>
#include <vtkSmartPointer.h>
#include <vtkTextMapper.h>
#include <vtkTextProperty.h>
#include <vtkUnsignedCharArray.h>
#include <vtkVersionMacros.h>

#include <QtTest/QtTest>
#include <algorithm>
#include <string>
#include <utility>
#include <vector>

#include "offscreen_frames.h"
#include "scene_view_caption.h"

namespace {

using deepcut::studio::CaptionActor;
using deepcut::test::studio::frame_of;
using deepcut::test::studio::offscreen_window;
using deepcut::test::studio::same_pixels;

/// How many sizes the counting captions (counting_caption()) measured their text at so far. Both of
/// a caption's mappers count (the measuring and the drawing one): drawing never calls GetSize.
int sizes_measured = 0;

/// The OpenGL text mapper, counting the caption's measurements (it measures through GetSize only).
class CountingTextMapper : public vtkOpenGLTextMapper {
 public:
  static CountingTextMapper* New();
  vtkTypeMacro(CountingTextMapper, vtkOpenGLTextMapper)
  void GetSize(vtkViewport* viewport, int size[2]) override {
    ++sizes_measured;
    Superclass::GetSize(viewport, size);
  }
};
vtkStandardNewMacro(CountingTextMapper);

/// Hands out counting text mappers where vtkTextMapper::New() is asked for one.
class CountingFactory : public vtkObjectFactory {
 public:
  static CountingFactory* New() {
    auto* factory = new CountingFactory;
    factory->InitializeObjectBase();
    return factory;
  }
  vtkTypeMacro(CountingFactory, vtkObjectFactory)
  const char* GetVTKSourceVersion() override { return VTK_SOURCE_VERSION; }
  const char* GetDescription() override { return "text mappers that count their measurements"; }

 protected:
  CountingFactory() {
    RegisterOverride("vtkTextMapper", "CountingTextMapper", "counting", 1,
                     [] { return static_cast<vtkObject*>(CountingTextMapper::New()); });
  }
};

/// While alive, VTK's object factory hands out counting text mappers in place of the OpenGL ones
/// (undone on every way out, so no later test gets them).
class CountingMappers {
 public:
  CountingMappers() {
    vtkObjectFactory::SetAllEnableFlags(0, "vtkTextMapper", "vtkOpenGLTextMapper");
    vtkObjectFactory::RegisterFactory(factory_);
  }
  ~CountingMappers() {
    vtkObjectFactory::UnRegisterFactory(factory_);
    vtkObjectFactory::SetAllEnableFlags(1, "vtkTextMapper", "vtkOpenGLTextMapper");
  }
  CountingMappers(const CountingMappers&) = delete;
  CountingMappers& operator=(const CountingMappers&) = delete;

 private:
  vtkNew<CountingFactory> factory_;
};

/// A caption whose text mappers count into sizes_measured (the caption's interface has no counter).
vtkSmartPointer<CaptionActor> counting_caption() {
  const CountingMappers counting;
  return vtkSmartPointer<CaptionActor>::New();
}

/// One renderer with the caption, one with the corner annotation, kept across frames (both keep
/// the size they drew at: the next fit starts there).
struct Pair {
  vtkSmartPointer<CaptionActor> ours;
  vtkNew<vtkCornerAnnotation> theirs;
  vtkNew<vtkRenderer> with_ours, with_theirs;
  Pair() : Pair(vtkSmartPointer<CaptionActor>::New()) {}
  explicit Pair(vtkSmartPointer<CaptionActor> caption) : ours(std::move(caption)) {
    theirs->SetMaximumFontSize(15);
    theirs->SetLinearFontScaleFactor(2);
    theirs->SetNonlinearFontScaleFactor(1);
    for (vtkTextProperty* style : {ours->GetTextProperty(), theirs->GetTextProperty()}) {
      style->SetColor(0.93, 0.93, 0.93);
      style->SetFontFamilyToArial();
      style->ShadowOn();
    }
    with_ours->AddViewProp(ours);
    with_theirs->AddViewProp(theirs);
    for (vtkRenderer* r : {with_ours.Get(), with_theirs.Get()}) r->SetBackground(0.13, 0.14, 0.16);
  }
  void set_text(const std::string& text) {
    ours->SetText(text);
    theirs->SetText(vtkCornerAnnotation::UpperLeft, text.c_str());
  }
};

// Whether any pixel is well above the background (at most 41): the text drew.
bool has_text(vtkUnsignedCharArray* a) {
  return std::any_of(a->GetPointer(0), a->GetPointer(0) + a->GetNumberOfValues(),
                     [](unsigned char c) { return c > 100; });
}

// The texts of the comparisons: one line, four lines, one line wider than most views.
const std::vector<std::string>& texts() {
  static const std::vector<std::string> all = {
      "cactus_1000000.glb  |  Materials",
      "model.glb  |  Mesh statistics\n999,656 triangles\n500,000 vertices\n3 materials",
      std::string(120, 'W') + "  |  Materials",
  };
  return all;
}

// Renders both renderers in `window` at its size and says how the frames differ ("" when they
// are the same and, where the caption is drawn, both show text).
std::string compare(vtkRenderWindow* window, Pair& pair, const std::string& what) {
  vtkSmartPointer<vtkUnsignedCharArray> a = frame_of(window, pair.with_ours);
  vtkSmartPointer<vtkUnsignedCharArray> b = frame_of(window, pair.with_theirs);
  const int* size = window->GetSize();
  const std::string where = what + " in " + std::to_string(size[0]) + " x " + std::to_string(size[1]) +
                            " at " + std::to_string(window->GetDPI()) + " dpi, size " +
                            std::to_string(pair.ours->font_size());
  if (!same_pixels(a, b)) return "frames differ: " + where;
  const bool drawn = pair.ours->font_size() >= CaptionActor::kMinimumFontSize &&
                     !std::string(pair.theirs->GetText(vtkCornerAnnotation::UpperLeft)).empty();
  if (drawn && !(has_text(a) && has_text(b))) return "no text drawn: " + where;
  return "";
}

// The text's extent at font size `size` in `window` (as the fit measures it).
std::pair<int, int> extent_at(vtkRenderWindow* window, vtkTextProperty* style, const std::string& text,
                              int size) {
  vtkNew<vtkRenderer> renderer;
  window->AddRenderer(renderer);
  vtkNew<vtkTextMapper> mapper;
  mapper->GetTextProperty()->ShallowCopy(style);
  mapper->GetTextProperty()->SetFontSize(size);
  mapper->SetInput(text.c_str());
  int e[2];
  mapper->GetSize(renderer, e);
  window->RemoveRenderer(renderer);
  return {e[0], e[1]};
}

// The smallest view extent whose 90% (as vtkCornerAnnotation rounds it) is `limit`.
int view_for(int limit) {
  int view = 1;
  while (static_cast<int>(0.9 * view) < limit) ++view;
  return view;
}

}  // namespace

class CaptionTest : public QObject {
  Q_OBJECT

 private slots:
  void frames_equal_the_corner_annotations();
  void frames_equal_where_the_text_just_fits();
  void tokens_are_drawn_as_given();
  void a_wide_view_measures_the_text_once();

 private:
  vtkSmartPointer<vtkRenderWindow> window_ = offscreen_window(200, 150);  // for every case
};

void CaptionTest::frames_equal_the_corner_annotations() {
  // Wide, narrow (the fit below the maximum), tiny (not drawn), back to wide, and sizes between.
  const std::vector<std::pair<int, int>> sizes = {{1000, 700}, {420, 300},  {160, 120}, {60, 40},
                                                  {24, 16},    {1000, 700}, {300, 500}, {700, 90}};
  for (const int dpi : {72, 96}) {
    window_->SetDPI(dpi);
    Pair pair;
    pair.set_text(texts().back());
    bool smaller = false;
    int with_text = 0;
    for (const auto& [w, h] : sizes) {
      // The view's size alone changes (twice: refitted, then not), then the text.
      window_->SetSize(w, h);
      for (const char* what : {"resized", "again"}) {
        const std::string error = compare(window_, pair, what);
        QVERIFY2(error.empty(), error.c_str());
      }
      for (const std::string& text : texts()) {
        pair.set_text(text);
        const std::string error = compare(window_, pair, "text " + std::to_string(&text - texts().data()));
        QVERIFY2(error.empty(), error.c_str());
        smaller |= pair.ours->font_size() < CaptionActor::kMaximumFontSize;
        with_text += pair.ours->font_size() >= CaptionActor::kMinimumFontSize;
      }
    }
    QVERIFY2(smaller, "some view was narrow enough for a smaller size");
    QVERIFY2(with_text >= 10, "most frames show text");
    // A new style, then the same text and size again (nothing refitted, the same frame).
    pair.ours->GetTextProperty()->SetColor(1.0, 0.6, 0.2);
    pair.theirs->GetTextProperty()->SetColor(1.0, 0.6, 0.2);
    for (const char* what : {"restyled", "restyled, again"}) {
      const std::string error = compare(window_, pair, what);
      QVERIFY2(error.empty(), error.c_str());
    }
    // Empty text draws nothing, blank text (it measures above 0 x 0 with this font: fitted and
    // drawn), then text again.
    pair.set_text("");
    QVERIFY(same_pixels(frame_of(window_, pair.with_ours), frame_of(window_, pair.with_theirs)));
    for (const char* blank : {" ", "\n", "  \n "}) {
      pair.set_text(blank);
      QVERIFY(same_pixels(frame_of(window_, pair.with_ours), frame_of(window_, pair.with_theirs)));
      window_->SetSize(500, 300);
      QVERIFY(same_pixels(frame_of(window_, pair.with_ours), frame_of(window_, pair.with_theirs)));
    }
    pair.set_text(texts()[0]);
    const std::string error = compare(window_, pair, "text after none");
    QVERIFY2(error.empty(), error.c_str());
  }
  window_->SetDPI(72);
}

void CaptionTest::frames_equal_where_the_text_just_fits() {
  // Views where 90% of the width (then the height) is the text's at size 8, and 2 pixels either
  // side: the caption's shortcut (fits at 8) and vtkCornerAnnotation's search (an extent equal to
  // its limit stops it) decide alike there. Each view is reached from a larger one (the search
  // starts at 15) and from a tiny one (it starts below 8 and goes up).
  Pair pair;
  for (const std::string& text : texts()) {
    const int width = extent_at(window_, pair.ours->GetTextProperty(), text, 8).first;
    const int edge = view_for(width);
    pair.set_text(text);
    QCOMPARE(static_cast<int>(0.9 * edge), width);  // (the sweep meets the edge)
    for (int w = edge - 2; w <= edge + 2; ++w) {
      for (const int before : {edge + 40, 16}) {
        window_->SetSize(before, 200);
        QVERIFY(same_pixels(frame_of(window_, pair.with_ours), frame_of(window_, pair.with_theirs)));
        window_->SetSize(w, 200);
        const std::string error = compare(
            window_, pair,
            "text " + std::to_string(&text - texts().data()) + " from " + std::to_string(before) + " wide");
        QVERIFY2(error.empty(), error.c_str());
      }
    }
  }
  const std::string& lines = texts()[1];
  const int height = extent_at(window_, pair.ours->GetTextProperty(), lines, 8).second;
  const int edge = view_for(height);
  pair.set_text(lines);
  QCOMPARE(static_cast<int>(0.9 * edge), height);
  bool fifteen = false, fourteen = false;
  for (int h = edge - 2; h <= edge + 2; ++h) {
    for (const int before : {700, 12}) {
      window_->SetSize(1000, before);
      QVERIFY(same_pixels(frame_of(window_, pair.with_ours), frame_of(window_, pair.with_theirs)));
      window_->SetSize(1000, h);
      const std::string error = compare(window_, pair, "4 lines from " + std::to_string(before) + " high");
      QVERIFY2(error.empty(), error.c_str());
      fifteen |= pair.ours->font_size() == 15;
      fourteen |= pair.ours->font_size() == 14;
    }
  }
  QVERIFY2(fifteen && fourteen, "the height sweep crosses from 15 to 14");
}

void CaptionTest::tokens_are_drawn_as_given() {
  // vtkCornerAnnotation deleted "<slice>" (an image viewer's token): its frame differs from the
  // caption's, and equals the caption's of the text without the token; the caption's equals a
  // plain text mapper's drawing of the text as given.
  window_->SetSize(600, 400);
  Pair with_token, without;
  with_token.set_text("<slice>.glb  |  Materials");
  without.set_text(".glb  |  Materials");
  vtkSmartPointer<vtkUnsignedCharArray> ours = frame_of(window_, with_token.with_ours);
  vtkSmartPointer<vtkUnsignedCharArray> theirs = frame_of(window_, with_token.with_theirs);
  QVERIFY(has_text(ours));
  QVERIFY(has_text(theirs));
  QVERIFY(!same_pixels(ours, theirs));
  QVERIFY(same_pixels(theirs, frame_of(window_, without.with_ours)));

  QCOMPARE(with_token.ours->font_size(), CaptionActor::kMaximumFontSize);
  vtkNew<vtkTextMapper> mapper;
  mapper->SetInput("<slice>.glb  |  Materials");
  vtkTextProperty* style = mapper->GetTextProperty();
  style->ShallowCopy(with_token.ours->GetTextProperty());
  style->SetFontSize(CaptionActor::kMaximumFontSize);
  style->SetJustificationToLeft();
  style->SetVerticalJustificationToTop();
  vtkNew<vtkActor2D> plain;
  plain->SetMapper(mapper);
  plain->SetPosition(5, 400 - 5);
  vtkNew<vtkRenderer> with_plain;
  with_plain->SetBackground(0.13, 0.14, 0.16);
  with_plain->AddViewProp(plain);
  QVERIFY(same_pixels(ours, frame_of(window_, with_plain)));
}

void CaptionTest::a_wide_view_measures_the_text_once() {
  Pair pair(counting_caption());
  sizes_measured = 0;
  window_->SetSize(1000, 700);
  pair.set_text("cactus_1000000.glb  |  Materials");
  frame_of(window_, pair.with_ours);
  QCOMPARE(pair.ours->font_size(), CaptionActor::kMaximumFontSize);
  QCOMPARE(sizes_measured, 1);
  pair.set_text("cactus_1000000.glb  |  Mesh statistics\n999,656 triangles");
  frame_of(window_, pair.with_ours);
  QCOMPARE(sizes_measured, 2);
  frame_of(window_, pair.with_ours);  // unchanged: no fit
  QCOMPARE(sizes_measured, 2);
  // Narrow: the search, more sizes, a smaller one.
  window_->SetSize(120, 90);
  frame_of(window_, pair.with_ours);
  QVERIFY(sizes_measured > 3);
  QVERIFY(pair.ours->font_size() < CaptionActor::kMaximumFontSize);
  // From a drawn size of 8 (fitted 4) into a view where the text at 6 is exactly at the limit:
  // size 8 is measured once (by the shortcut, then reused as the search's start), then 7 and 6.
  const std::string& text = texts()[0];
  vtkTextProperty* style = pair.ours->GetTextProperty();
  pair.set_text(text);
  window_->SetSize(view_for(extent_at(window_, style, text, 4).first), 700);
  frame_of(window_, pair.with_ours);
  QCOMPARE(pair.ours->font_size(), 8);
  const int before = sizes_measured;
  window_->SetSize(view_for(extent_at(window_, style, text, 6).first), 700);
  frame_of(window_, pair.with_ours);
  QCOMPARE(pair.ours->font_size(), 12);
  QCOMPARE(sizes_measured - before, 3);
}

QTEST_APPLESS_MAIN(CaptionTest)
#include "caption_test.moc"
