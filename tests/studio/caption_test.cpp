// SPDX-License-Identifier: MIT
// The view's caption (app/studio/scene_view_caption.h) under xvfb-run: its frames equal those of
// vtkCornerAnnotation set up as the studio set it up before (upper left text, size fitted, doubled,
// at most 15), pixel for pixel, for one-line and several-line texts in views from wide to a few
// dozen pixels, as the text, the view's size and the style change; in a wide view the text is
// measured at one size only, in a narrow one the size is searched (and smaller).
#include <vtkCornerAnnotation.h>
#include <vtkNew.h>
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>
#include <vtkSmartPointer.h>
#include <vtkTextProperty.h>
#include <vtkUnsignedCharArray.h>

#include <QtTest/QtTest>
#include <algorithm>
#include <string>
#include <utility>
#include <vector>

#include "scene_view_caption.h"

namespace {

using deepcut::studio::CaptionActor;

/// One renderer with the caption, one with the corner annotation, kept across frames (both keep
/// the size they drew at: the next fit starts there).
struct Pair {
  vtkNew<CaptionActor> ours;
  vtkNew<vtkCornerAnnotation> theirs;
  vtkNew<vtkRenderer> with_ours, with_theirs;
  Pair() {
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

vtkSmartPointer<vtkUnsignedCharArray> frame(vtkRenderWindow* window, vtkRenderer* renderer) {
  window->AddRenderer(renderer);
  window->Render();
  const int* size = window->GetSize();
  auto pixels = vtkSmartPointer<vtkUnsignedCharArray>::New();
  window->GetPixelData(0, 0, size[0] - 1, size[1] - 1, 1, pixels);
  window->RemoveRenderer(renderer);
  return pixels;
}

bool same(vtkUnsignedCharArray* a, vtkUnsignedCharArray* b) {
  return a->GetNumberOfValues() == b->GetNumberOfValues() &&
         std::equal(a->GetPointer(0), a->GetPointer(0) + a->GetNumberOfValues(), b->GetPointer(0));
}

// Whether any pixel is brighter than the background (the text drew).
bool has_text(vtkUnsignedCharArray* a) {
  return std::any_of(a->GetPointer(0), a->GetPointer(0) + a->GetNumberOfValues(),
                     [](unsigned char c) { return c > 200; });
}

}  // namespace

class CaptionTest : public QObject {
  Q_OBJECT

 private slots:
  void initTestCase();
  void frames_equal_the_corner_annotations();
  void a_wide_view_measures_the_text_once();

 private:
  // One window for every case (see surface_mapper_test.cpp).
  vtkNew<vtkRenderWindow> window_;
};

void CaptionTest::initTestCase() {
  window_->SetOffScreenRendering(1);
  window_->SetSize(200, 150);
}

void CaptionTest::frames_equal_the_corner_annotations() {
  Pair pair;
  const std::vector<std::string> texts = {
      "cactus_1000000.glb  |  Materials",
      "model.glb  |  Mesh statistics\n999,656 triangles\n500,000 vertices\n3 materials",
      std::string(120, 'W') + "  |  Materials",
  };
  // Wide, narrow (the fit below the maximum), tiny (not drawn), back to wide, and sizes between.
  const std::vector<std::pair<int, int>> sizes = {{1000, 700}, {420, 300},  {160, 120}, {60, 40},
                                                  {24, 16},    {1000, 700}, {300, 500}, {700, 90}};
  bool drew = false, smaller = false;
  int frames = 0;
  for (const auto& [w, h] : sizes) {
    window_->SetSize(w, h);
    for (const std::string& text : texts) {
      pair.set_text(text);
      vtkSmartPointer<vtkUnsignedCharArray> a = frame(window_, pair.with_ours);
      vtkSmartPointer<vtkUnsignedCharArray> b = frame(window_, pair.with_theirs);
      const std::string where = std::to_string(w) + " x " + std::to_string(h) + ", text " +
                                std::to_string(&text - texts.data()) + ", size " +
                                std::to_string(pair.ours->font_size());
      QVERIFY2(same(a, b), where.c_str());
      drew |= has_text(a);
      smaller |= pair.ours->font_size() < CaptionActor::kMaximumFontSize;
      ++frames;
    }
  }
  QVERIFY(drew);
  QVERIFY2(smaller, "some view was narrow enough for a smaller size");
  // A new style, then the same text and size again (nothing refitted, the same frame).
  pair.ours->GetTextProperty()->SetColor(1.0, 0.6, 0.2);
  pair.theirs->GetTextProperty()->SetColor(1.0, 0.6, 0.2);
  QVERIFY(same(frame(window_, pair.with_ours), frame(window_, pair.with_theirs)));
  QVERIFY(same(frame(window_, pair.with_ours), frame(window_, pair.with_theirs)));
  // Empty text draws nothing, then text again.
  pair.set_text("");
  QVERIFY(same(frame(window_, pair.with_ours), frame(window_, pair.with_theirs)));
  pair.set_text(texts[0]);
  QVERIFY(same(frame(window_, pair.with_ours), frame(window_, pair.with_theirs)));
  QVERIFY(frames > 0);
}

void CaptionTest::a_wide_view_measures_the_text_once() {
  Pair pair;
  window_->SetSize(1000, 700);
  pair.set_text("cactus_1000000.glb  |  Materials");
  frame(window_, pair.with_ours);
  QCOMPARE(pair.ours->font_size(), CaptionActor::kMaximumFontSize);
  QCOMPARE(pair.ours->sizes_measured(), 1);
  pair.set_text("cactus_1000000.glb  |  Mesh statistics\n999,656 triangles");
  frame(window_, pair.with_ours);
  QCOMPARE(pair.ours->sizes_measured(), 2);
  frame(window_, pair.with_ours);  // unchanged: no fit
  QCOMPARE(pair.ours->sizes_measured(), 2);
  // Narrow: the search, more sizes, a smaller one.
  window_->SetSize(120, 90);
  frame(window_, pair.with_ours);
  QVERIFY(pair.ours->sizes_measured() > 3);
  QVERIFY(pair.ours->font_size() < CaptionActor::kMaximumFontSize);
}

QTEST_APPLESS_MAIN(CaptionTest)
#include "caption_test.moc"
