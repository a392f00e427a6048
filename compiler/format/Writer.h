// The formatter's output: text put in lines, each begun at an indentation, with at most one
// blank line in a row and no blank line just inside an opening brace. It knows columns (in
// characters), so that the layout can align continuation lines and measure short forms.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>

namespace moire::format {

class Writer {
  public:
    // The column a short form (a block kept on one line) must end within.
    static constexpr int kWidth = 100;

    // The indentation a line gets when put() begins it.
    int indent = 0;

    // Appends `s`: at `indent` when no line is open (or a break is pending), else after one
    // space when `space`. `s` may hold line breaks (a block comment); its last line counts.
    void put(std::string_view s, bool space);
    // Ends the open line, if any.
    void newline();
    // Ends the open line and leaves one blank line, unless the text is empty, already ends
    // with a blank line, or its last line opens a block.
    void blank();
    // The next put() begins a new line (after a line comment).
    void requireBreak() { breakPending_ = lineOpen_; }
    bool lineOpen() const { return lineOpen_ && !breakPending_; }

    int column() const { return column_; }         // after the last character put
    int lineIndent() const { return lineIndent_; } // of the open line
    size_t linesEnded() const { return lines_; }

    // A point to go back to: reset() forgets everything put since mark().
    struct Mark {
        size_t size = 0, lines = 0;
        int column = 0, lineIndent = 0;
        bool lineOpen = false, breakPending = false, afterOpen = false;
    };
    Mark mark() const {
        return {out_.size(), lines_, column_, lineIndent_, lineOpen_, breakPending_, afterOpen_};
    }
    void reset(const Mark& m);

    // The text, its last line ended.
    std::string finish();

    // The width of `s` in characters (UTF-8 continuation bytes do not count).
    static int width(std::string_view s);

  private:
    std::string out_;
    size_t lines_ = 0;
    int column_ = 0, lineIndent_ = 0;
    bool lineOpen_ = false, breakPending_ = false;
    bool afterOpen_ = false; // the last thing put was '{'
};

} // namespace moire::format
