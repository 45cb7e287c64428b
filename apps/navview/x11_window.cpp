// Window output through Xlib: the composite is copied into a 32-bit XImage and put on a
// plain window, repainted on Expose; the mouse and keys move the 3-D view (a left drag orbits,
// the wheel zooms, keys as kViewHelpLines says); closing the window, q or Esc ends navview.
#include "image_output.hpp"

#include <array>
#include <cstdint>
#include <optional>
#include <vector>

#include <X11/Xlib.h>
#include <X11/Xutil.h>
#include <X11/keysym.h>
#undef Status  // Xlib's macro for int; nav::Status is meant below

namespace navview {
namespace {

/// One top-level window on a 24-bit TrueColor display.
class X11Window final : public ImageOutput {
 public:
  X11Window(Display* display, Window window, Atom delete_message)
      : display_(display),
        window_(window),
        delete_message_(delete_message),
        gc_(XCreateGC(display, window, 0, nullptr)) {}

  ~X11Window() override {
    release_image();
    XFreeGC(display_, gc_);
    XDestroyWindow(display_, window_);
    XCloseDisplay(display_);
  }
  X11Window(const X11Window&) = delete;
  X11Window& operator=(const X11Window&) = delete;

  nav::Status show(const cv::Mat& image) override {
    if (image_ == nullptr || image_->width != image.cols || image_->height != image.rows) {
      release_image();
      pixels_.assign(static_cast<std::size_t>(image.cols) * static_cast<std::size_t>(image.rows), 0);
      image_ = XCreateImage(display_, DefaultVisual(display_, DefaultScreen(display_)), 24, ZPixmap, 0,
                            reinterpret_cast<char*>(pixels_.data()), static_cast<unsigned>(image.cols),
                            static_cast<unsigned>(image.rows), 32, 0);
      if (image_ == nullptr) return nav::Error{.message = "Xlib could not create the window's image"};
      XResizeWindow(display_, window_, static_cast<unsigned>(image.cols), static_cast<unsigned>(image.rows));
    }
    for (int y = 0; y < image.rows; ++y) {
      const std::uint8_t* bgr = image.ptr<std::uint8_t>(y);
      std::uint32_t* out = &pixels_[static_cast<std::size_t>(y) * static_cast<std::size_t>(image.cols)];
      for (int x = 0; x < image.cols; ++x, bgr += 3)
        out[x] = (std::uint32_t{bgr[2]} << 16) | (std::uint32_t{bgr[1]} << 8) | bgr[0];
    }
    paint();
    return nav::Done{};
  }

  bool poll_events(nav::view::ViewControl& view) override {
    bool changed = false;
    while (XPending(display_) > 0) {
      XEvent event;
      XNextEvent(display_, &event);
      if (event.type == Expose && event.xexpose.count == 0) paint();
      if (event.type == ClientMessage && static_cast<Atom>(event.xclient.data.l[0]) == delete_message_) closed_ = true;
      changed = handle_input(event, view) || changed;
    }
    closed_ = closed_ || view.quit_requested();
    return changed;
  }

  bool closed() const override { return closed_; }

 private:
  /// Moves `view` by a mouse or key event; true when it did.
  bool handle_input(const XEvent& event, nav::view::ViewControl& view) {
    if (event.type == ButtonPress && event.xbutton.button == Button1) {
      dragging_ = true;
      drag_from_ = {event.xbutton.x, event.xbutton.y};
    } else if (event.type == ButtonRelease && event.xbutton.button == Button1) {
      dragging_ = false;
    } else if (event.type == ButtonPress && (event.xbutton.button == Button4 || event.xbutton.button == Button5)) {
      view.wheel(event.xbutton.button == Button4 ? 1 : -1);
      return true;
    } else if (event.type == MotionNotify && dragging_) {
      view.drag(event.xmotion.x - drag_from_[0], event.xmotion.y - drag_from_[1]);
      drag_from_ = {event.xmotion.x, event.xmotion.y};
      return true;
    } else if (event.type == KeyPress) {
      XKeyEvent key_event = event.xkey;
      const auto key = view_key(XLookupKeysym(&key_event, 0));
      if (!key) return false;
      view.key(*key);
      return true;
    }
    return false;
  }

  /// The view key of a key symbol, if it is one.
  static std::optional<nav::view::ViewKey> view_key(KeySym symbol) {
    using nav::view::ViewKey;
    switch (symbol) {
      case XK_Left:
        return ViewKey::orbit_left;
      case XK_Right:
        return ViewKey::orbit_right;
      case XK_Up:
        return ViewKey::orbit_up;
      case XK_Down:
        return ViewKey::orbit_down;
      case XK_plus:
      case XK_equal:
      case XK_KP_Add:
        return ViewKey::zoom_in;
      case XK_minus:
      case XK_KP_Subtract:
        return ViewKey::zoom_out;
      case XK_r:
        return ViewKey::reset;
      case XK_h:
      case XK_question:
        return ViewKey::help;
      case XK_q:
      case XK_Escape:
        return ViewKey::quit;
      default:
        return std::nullopt;
    }
  }

  void paint() {
    if (image_ == nullptr) return;
    XPutImage(display_, window_, gc_, image_, 0, 0, 0, 0, static_cast<unsigned>(image_->width),
              static_cast<unsigned>(image_->height));
    XFlush(display_);
  }

  /// Frees the XImage but not the pixels, which pixels_ owns.
  void release_image() {
    if (image_ == nullptr) return;
    image_->data = nullptr;
    XDestroyImage(image_);
    image_ = nullptr;
  }

  Display* display_;
  Window window_;
  Atom delete_message_;
  GC gc_;
  XImage* image_ = nullptr;
  std::vector<std::uint32_t> pixels_;
  bool closed_ = false;
  bool dragging_ = false;
  std::array<int, 2> drag_from_{};  ///< the pointer's last position while dragging
};

}  // namespace

nav::Result<std::unique_ptr<ImageOutput>> open_window(const std::string& title) {
  Display* display = XOpenDisplay(nullptr);
  if (display == nullptr) return nav::Error{.message = "cannot open the X display ($DISPLAY); use --headless"};
  const int screen = DefaultScreen(display);
  if (DefaultDepth(display, screen) != 24) {
    XCloseDisplay(display);
    return nav::Error{.message = "navview needs a 24-bit TrueColor display; use --headless"};
  }
  const Window window = XCreateSimpleWindow(display, RootWindow(display, screen), 0, 0, 640, 480, 0,
                                            BlackPixel(display, screen), BlackPixel(display, screen));
  XStoreName(display, window, title.c_str());
  XSelectInput(
      display, window,
      ExposureMask | StructureNotifyMask | ButtonPressMask | ButtonReleaseMask | Button1MotionMask | KeyPressMask);
  Atom delete_message = XInternAtom(display, "WM_DELETE_WINDOW", False);
  XSetWMProtocols(display, window, &delete_message, 1);
  XMapWindow(display, window);
  XFlush(display);
  return std::unique_ptr<ImageOutput>(new X11Window(display, window, delete_message));
}

}  // namespace navview
