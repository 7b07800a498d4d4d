#include "sim/task/instruction_parser.h"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <sstream>
#include <unordered_map>
#include <vector>

namespace culinarycut::task {
namespace {

constexpr double kSameValueTolerance = 1e-9;
// The largest integer the parser reads ("into 7 pieces", "30%", the parts of "n/d"); longer digit
// strings are refused rather than overflowed.
constexpr long long kMaxNumber = 1000000;

bool IsDigits(const std::string& word) {
  if (word.empty()) return false;
  for (char c : word) {
    if (c < '0' || c > '9') return false;
  }
  return true;
}

bool IsDecimal(const std::string& word) {
  return !word.empty() && word.back() >= '0' && word.back() <= '9' &&
         word.find('.') != std::string::npos;
}

// Words that matter only in a phrase: "from the right", "along its length", "3-way", "per cent".
enum class Tag {
  kOther, kA, kInto, kIn, kWay, kCuts, kHalf, kPercent, kPer, kCent, kRatio, kLeft, kRight,
  kTop, kAlong, kIts, kThe, kLength, kLong, kLengthwise, kBack, kAnd, kForth, kSideBefore,
  kToward, kSideAfter
};

// Everything a word can mean to the parser, looked up once per token.
struct WordInfo {
  Tag tag = Tag::kOther;
  int number = -1;          // "three" -> 3, "twenty" -> 20
  bool tens = false;        // twenty..ninety, which may take a unit ("twenty five")
  int denominator = 0;      // "tenths" -> 10, "half" -> 2
  int ordinal_pieces = 0;   // "into fifths" -> 5
  int style = -1;           // a CutStyle
  const std::string* food = nullptr;
  bool middle = false;
  bool split_word = false;
  bool piece_noun = false;
  bool piece_adjective = false;  // "3 equal-sized pieces"
};

const std::unordered_map<std::string, WordInfo>& Lexicon() {
  static const std::unordered_map<std::string, WordInfo> lexicon = [] {
    std::unordered_map<std::string, WordInfo> words;
    const char* units[] = {"zero",    "one",     "two",       "three",    "four",
                           "five",    "six",     "seven",     "eight",    "nine",
                           "ten",     "eleven",  "twelve",    "thirteen", "fourteen",
                           "fifteen", "sixteen", "seventeen", "eighteen", "nineteen"};
    for (int i = 0; i < 20; ++i) words[units[i]].number = i;
    const char* tens[] = {"twenty", "thirty", "forty", "fifty", "sixty", "seventy", "eighty",
                          "ninety"};
    for (int i = 0; i < 8; ++i) {
      words[tens[i]].number = 20 + 10 * i;
      words[tens[i]].tens = true;
    }
    const std::pair<const char*, int> denominators[] = {
        {"half", 2},     {"third", 3},     {"thirds", 3},  {"quarter", 4},  {"quarters", 4},
        {"fourth", 4},   {"fourths", 4},   {"fifth", 5},   {"fifths", 5},   {"sixth", 6},
        {"sixths", 6},   {"seventh", 7},   {"sevenths", 7}, {"eighth", 8},  {"eighths", 8},
        {"ninth", 9},    {"ninths", 9},    {"tenth", 10},  {"tenths", 10},  {"hundredth", 100},
        {"hundredths", 100}};
    for (const auto& [word, value] : denominators) words[word].denominator = value;
    const std::pair<const char*, int> ordinal_pieces[] = {
        {"thirds", 3}, {"quarters", 4}, {"fourths", 4}, {"fifths", 5}, {"sixths", 6},
        {"sevenths", 7}, {"eighths", 8}, {"ninths", 9}, {"tenths", 10}};
    for (const auto& [word, value] : ordinal_pieces) words[word].ordinal_pieces = value;
    const std::pair<const char*, CutStyle> styles[] = {
        {"normal", CutStyle::kNormal},         {"perpendicular", CutStyle::kNormal},
        {"bias", CutStyle::kBias},             {"diagonal", CutStyle::kBias},
        {"diagonally", CutStyle::kBias},       {"angled", CutStyle::kBias},
        {"oblique", CutStyle::kBias},          {"obliquely", CutStyle::kBias},
        {"slanted", CutStyle::kBias},          {"slanting", CutStyle::kBias},
        {"guillotine", CutStyle::kGuillotine}, {"guillotined", CutStyle::kGuillotine},
        {"saw", CutStyle::kSaw},               {"sawing", CutStyle::kSaw},
        {"saws", CutStyle::kSaw},              {"sawed", CutStyle::kSaw},
        {"sawn", CutStyle::kSaw}};
    for (const auto& [word, style] : styles) words[word].style = static_cast<int>(style);
    for (const std::string& food : KnownFoods()) {
      words[food].food = &food;
      words[food + "s"].food = &food;
      if (food == "peach") words["peaches"].food = &food;
      if (food == "strawberry") words["strawberries"].food = &food;
    }
    for (const char* word : {"middle", "center", "centre", "midpoint", "mid", "midway",
                             "centerline", "centreline", "midline"}) {
      words[word].middle = true;
    }
    // The paper's "at the first split boundary" names one boundary of an unknown split.
    for (const char* word :
         {"split", "splits", "splitting", "divide", "divided", "boundary", "boundaries"}) {
      words[word].split_word = true;
    }
    for (const char* word : {"piece", "pieces", "slice", "slices", "part", "parts", "segment",
                             "segments", "chunk", "chunks", "portion", "portions", "section",
                             "sections", "bit", "bits", "round", "rounds", "lengths", "wedges"}) {
      words[word].piece_noun = true;
    }
    for (const char* word : {"equal", "equally", "even", "evenly", "same", "sized", "size",
                             "identical", "uniform", "similar", "length", "long", "thick", "wide",
                             "smaller", "separate"}) {
      words[word].piece_adjective = true;
    }
    const std::pair<const char*, Tag> tags[] = {
        {"a", Tag::kA},           {"an", Tag::kA},         {"into", Tag::kInto},
        {"in", Tag::kIn},         {"way", Tag::kWay},      {"cuts", Tag::kCuts},
        {"halfway", Tag::kHalf},  {"halves", Tag::kHalf},  {"%", Tag::kPercent},
        {"percent", Tag::kPercent}, {"pct", Tag::kPercent}, {"per", Tag::kPer},
        {"cent", Tag::kCent},     {"ratio", Tag::kRatio},  {"ratios", Tag::kRatio},
        {"left", Tag::kLeft},     {"right", Tag::kRight},  {"top", Tag::kTop},
        {"above", Tag::kTop},     {"along", Tag::kAlong},  {"its", Tag::kIts},
        {"the", Tag::kThe},       {"length", Tag::kLength}, {"long", Tag::kLong},
        {"lengthwise", Tag::kLengthwise}, {"back", Tag::kBack}, {"and", Tag::kAnd},
        {"forth", Tag::kForth},   {"from", Tag::kSideBefore}, {"toward", Tag::kToward},
        {"towards", Tag::kToward}, {"to", Tag::kSideBefore}, {"far", Tag::kSideBefore},
        {"on", Tag::kSideBefore}, {"side", Tag::kSideAfter}, {"end", Tag::kSideAfter},
        {"hand", Tag::kSideAfter}, {"edge", Tag::kSideAfter}, {"tip", Tag::kSideAfter}};
    for (const auto& [word, tag] : tags) words[word].tag = tag;
    words["half"].tag = Tag::kHalf;
    return words;
  }();
  return lexicon;
}

const WordInfo& Lookup(const std::string& word) {
  static const WordInfo kUnknown;
  const auto& lexicon = Lexicon();
  const auto found = lexicon.find(word);
  return found == lexicon.end() ? kUnknown : found->second;
}

struct Token {
  std::string text;
  const WordInfo* info = nullptr;
  bool consumed = false;  // already read as part of a quantity or a piece count
};

// Lower case; words, integers, decimals ("0.3", ".3") and fractions ("1/3") are tokens; '%' is
// its own token; apostrophes vanish ("banana's" -> "bananas"); everything else separates.
std::vector<Token> Tokenize(const std::string& text) {
  std::vector<Token> tokens;
  std::string current;
  const auto flush = [&] {
    if (!current.empty()) tokens.push_back({current, &Lookup(current)});
    current.clear();
  };
  const auto is_digit = [](char c) { return c >= '0' && c <= '9'; };
  for (size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    const bool next_is_digit = i + 1 < text.size() && is_digit(text[i + 1]);
    const bool current_is_number =
        !current.empty() && is_digit(current.back()) && current.find('.') == std::string::npos;
    if (is_digit(c) || (c >= 'a' && c <= 'z')) {
      current.push_back(c);
    } else if (c >= 'A' && c <= 'Z') {
      current.push_back(static_cast<char>(c - 'A' + 'a'));
    } else if (c == '.' && next_is_digit && (current.empty() || current_is_number)) {
      current.push_back('.');
    } else if (c == '/' && next_is_digit && current_is_number) {
      current.push_back('/');
    } else if (c == '\'') {
      continue;
    } else {
      flush();
      if (c == '%') tokens.push_back({"%", &Lookup("%")});
    }
  }
  flush();
  return tokens;
}

std::string Join(const std::vector<Token>& tokens, size_t begin, size_t end) {
  std::string phrase;
  for (size_t i = begin; i < end && i < tokens.size(); ++i) {
    phrase += (phrase.empty() ? "" : " ") + tokens[i].text;
  }
  return phrase;
}

std::string Format(double value) {
  std::ostringstream text;
  text << value;
  return text.str();
}

struct Mention {
  double value = 0.0;
  std::string phrase;  // the words it was read from, for messages
};

// Everything the text says, before conflicts are resolved.
struct Reading {
  std::vector<Mention> ratios;
  std::vector<Mention> piece_counts;
  std::vector<std::pair<std::string, std::string>> foods;   // (food, word)
  std::vector<std::pair<CutStyle, std::string>> styles;     // (style, word)
  std::vector<std::pair<DirectionalReference, std::string>> references;
  bool middle = false;
  std::string middle_word;
  bool ratio_word = false;
  bool split_word = false;
  bool toward_side = false;  // "toward the right end", read as measured from the left
};

class Parser {
 public:
  explicit Parser(const std::string& text) : text_(text), tokens_(Tokenize(text)) {}

  PartialCutSpec Parse() {
    if (tokens_.empty()) {
      Fail("it is empty; say what to cut and where, e.g. \"cut the banana at 0.3 ratio from "
           "the left\"");
    }
    ReadQuantities();
    ReadPieceCounts();
    ReadKeywords();
    return Resolve();
  }

  [[noreturn]] void Fail(const std::string& what) const {
    throw TaskError("cannot parse instruction \"" + text_ + "\": " + what);
  }

 private:
  bool Free(size_t at) const { return at < tokens_.size() && !tokens_[at].consumed; }
  const WordInfo& Info(size_t at) const {
    static const WordInfo kPastTheEnd;
    return at < tokens_.size() ? *tokens_[at].info : kPastTheEnd;
  }
  Tag TagAt(size_t at) const { return Info(at).tag; }

  void Consume(size_t begin, size_t end) {
    for (size_t i = begin; i < end && i < tokens_.size(); ++i) tokens_[i].consumed = true;
  }

  void AddRatio(double value, size_t begin, size_t end) {
    reading_.ratios.push_back({value, Join(tokens_, begin, end)});
    Consume(begin, end);
  }

  void AddPieces(int pieces, size_t begin, size_t end) {
    reading_.piece_counts.push_back({static_cast<double>(pieces), Join(tokens_, begin, end)});
    Consume(begin, end);
  }

  // Tokens of "%", "percent" or "per cent" at `at`; 0 if none.
  int PercentLength(size_t at) const {
    if (TagAt(at) == Tag::kPercent) return 1;
    return TagAt(at) == Tag::kPer && TagAt(at + 1) == Tag::kCent ? 2 : 0;
  }

  // A digit string as a number; fails when it exceeds kMaxNumber (`phrase` names it, e.g. the
  // whole "n/d").
  long long Number(const std::string& digits, const std::string& phrase = "") const {
    errno = 0;
    char* end = nullptr;
    const long long value = std::strtoll(digits.c_str(), &end, 10);
    if (errno == ERANGE || end != digits.c_str() + digits.size() || value > kMaxNumber) {
      Fail("the number '" + (phrase.empty() ? digits : phrase) + "' is too large; a ratio lies " +
           "between 0.1 and 0.9 (e.g. 0.3, 30%, 1/3) and a split makes 3, 4 or 5 pieces");
    }
    return value;
  }

  // An integer in digits or words ("7", "three", "twenty five") at `at`; 0 tokens if none.
  int ReadInteger(size_t at, int* value) const {
    if (at >= tokens_.size()) return 0;
    const std::string& word = tokens_[at].text;
    if (IsDigits(word)) {
      *value = static_cast<int>(Number(word));
      return 1;
    }
    const WordInfo& info = Info(at);
    if (info.number < 0) return 0;
    *value = info.number;
    const WordInfo& unit = Info(at + 1);
    if (info.tens && unit.number > 0 && unit.number < 10) {
      *value += unit.number;
      return 2;
    }
    return 1;
  }

  // Decimals, percentages, "n/d", word fractions ("three tenths", "a quarter") and "half(way)".
  void ReadQuantities() {
    for (size_t i = 0; i < tokens_.size(); ++i) {
      if (!Free(i)) continue;
      const std::string& word = tokens_[i].text;
      if (IsDecimal(word)) {
        const double value = std::strtod(word.c_str(), nullptr);
        const int percent = PercentLength(i + 1);
        AddRatio(percent > 0 ? value / 100.0 : value, i, i + 1 + percent);
        continue;
      }
      if (const size_t slash = word.find('/'); slash != std::string::npos) {
        const long long numerator = Number(word.substr(0, slash), word);
        const long long denominator = Number(word.substr(slash + 1), word);
        if (denominator == 0) {
          Fail("the fraction '" + word + "' divides by zero; write a ratio e.g. as 1/3 or 0.3");
        }
        AddRatio(static_cast<double>(numerator) / static_cast<double>(denominator), i, i + 1);
        continue;
      }
      const bool article = TagAt(i) == Tag::kA;
      int number = 0;
      const int number_length = article ? 0 : ReadInteger(i, &number);
      if (number_length > 0) {
        if (const int percent = PercentLength(i + number_length); percent > 0) {
          AddRatio(number / 100.0, i, i + number_length + percent);
          continue;
        }
      }
      // A numerator ("a", "one", "3") directly before a denominator word.
      const int numerator = article ? 1 : number;
      const int numerator_length = article ? 1 : number_length;
      if (numerator_length > 0 && numerator > 0 && Free(i + numerator_length)) {
        if (const int denominator = Info(i + numerator_length).denominator; denominator > 0) {
          AddRatio(static_cast<double>(numerator) / denominator, i, i + numerator_length + 1);
          continue;
        }
      }
      if (TagAt(i) == Tag::kHalf) AddRatio(0.5, i, i + 1);
      if (TagAt(i) == Tag::kRatio) reading_.ratio_word = true;
    }
  }

  // "into 3 pieces", "three equal parts", "a 4-way split", "into fifths", "two cuts".
  void ReadPieceCounts() {
    for (size_t i = 0; i < tokens_.size(); ++i) {
      if (!Free(i)) continue;
      const bool after_into = i > 0 && (TagAt(i - 1) == Tag::kInto || TagAt(i - 1) == Tag::kIn);
      if (const int pieces = Info(i).ordinal_pieces; pieces > 0 && after_into) {
        AddPieces(pieces, i, i + 1);
        continue;
      }
      int number = 0;
      const int length = ReadInteger(i, &number);
      if (length == 0) continue;
      size_t next = i + length;
      while (Info(next).piece_adjective) ++next;
      if (Info(next).piece_noun || TagAt(next) == Tag::kWay) {
        AddPieces(number, i, next + 1);
      } else if (TagAt(next) == Tag::kCuts) {
        // n cuts make n + 1 pieces; "1 cut" is just a single cut.
        if (number >= 2) AddPieces(number + 1, i, next + 1);
        Consume(i, next + 1);
      } else if (after_into) {
        AddPieces(number, i, i + length);
      } else if (!(number == 1 && Info(i + length).food)) {  // "cut one apple" is fine
        // A number that is no quantity, fraction, percentage or piece count: "cut the cucumber
        // three times" must not quietly become a single cut.
        Fail("the number '" + Join(tokens_, i, i + length) + "' is neither a ratio (e.g. 0.3 "
             "ratio, 30%) nor a piece count (e.g. into 3 pieces)");
      }
      i += length - 1;  // a two-word number ("twenty five") is read once
    }
  }

  // A side word: "left" always; "right" only as a place ("the right", "right end"), never in
  // "right in the middle".
  bool IsSide(size_t at) const {
    if (TagAt(at) == Tag::kLeft) return true;
    if (TagAt(at) != Tag::kRight) return false;
    const Tag before = at > 0 ? TagAt(at - 1) : Tag::kOther;
    return before == Tag::kThe || before == Tag::kIts || before == Tag::kSideBefore ||
           before == Tag::kToward || TagAt(at + 1) == Tag::kSideAfter;
  }

  // "toward(s) [the|its] <side>": counted from the other end, moving toward this one.
  bool AfterToward(size_t at) const {
    if (at > 0 && TagAt(at - 1) == Tag::kToward) return true;
    return at > 1 && (TagAt(at - 1) == Tag::kThe || TagAt(at - 1) == Tag::kIts) &&
           TagAt(at - 2) == Tag::kToward;
  }

  void ReadKeywords() {
    for (size_t i = 0; i < tokens_.size(); ++i) {
      const WordInfo& info = Info(i);
      const Tag tag = info.tag;
      if (info.food) {
        reading_.foods.emplace_back(*info.food, tokens_[i].text);
      } else if (info.style >= 0) {
        reading_.styles.emplace_back(static_cast<CutStyle>(info.style), tokens_[i].text);
      } else if (tag == Tag::kBack && TagAt(i + 1) == Tag::kAnd && TagAt(i + 2) == Tag::kForth) {
        reading_.styles.emplace_back(CutStyle::kSaw, "back and forth");
      } else if (info.middle) {
        reading_.middle = true;
        reading_.middle_word = tokens_[i].text;
      } else if (info.split_word) {
        reading_.split_word = true;
      } else if (IsSide(i)) {
        // "toward the right end" counts from the left (the paper's "at the third boundary toward
        // the right end"), so it sets the opposite reference.
        const bool toward = AfterToward(i);
        const bool left = (tag == Tag::kLeft) != toward;
        reading_.references.emplace_back(
            left ? DirectionalReference::kLeft : DirectionalReference::kRight,
            toward ? "toward the " + tokens_[i].text : tokens_[i].text);
        reading_.toward_side = reading_.toward_side || toward;
      } else if (tag == Tag::kTop) {
        reading_.references.emplace_back(DirectionalReference::kTop, tokens_[i].text);
      } else if (tag == Tag::kLengthwise ||
                 (tag == Tag::kAlong &&
                  (TagAt(i + 1) == Tag::kIts || TagAt(i + 1) == Tag::kThe) &&
                  (TagAt(i + 2) == Tag::kLength || TagAt(i + 2) == Tag::kLong))) {
        reading_.references.emplace_back(DirectionalReference::kAlongLength, "along its length");
      }
    }
  }

  DirectionalReference ResolveReference() const {
    bool left = false;
    bool right = false;
    for (const auto& [reference, word] : reading_.references) {
      left = left || reference == DirectionalReference::kLeft;
      right = right || reference == DirectionalReference::kRight;
    }
    if (left && right) {
      Fail(std::string("it names both the left and the right") +
           (reading_.toward_side ? " ('toward the right end' counts from the left, 'toward the "
                                   "left end' from the right)"
                                 : "") +
           "; say which end the position is measured from");
    }
    // Left or right moves a ratio cut, so it outranks "from the top" and "along its length".
    if (left) return DirectionalReference::kLeft;
    if (right) return DirectionalReference::kRight;
    return reading_.references.empty() ? DirectionalReference::kNone
                                       : reading_.references.front().first;
  }

  PartialCutSpec Resolve() const {
    PartialCutSpec partial;
    for (const auto& [food, word] : reading_.foods) {
      if (!partial.target_object.empty() && partial.target_object != food) {
        Fail("it names two foods, '" + partial.target_object + "' and '" + food +
             "'; an instruction has one target object");
      }
      partial.target_object = food;
    }
    for (const auto& [style, word] : reading_.styles) {
      if (partial.style && *partial.style != style) {
        Fail("it names two cut styles, " + Name(*partial.style) + " and " + Name(style) +
             " ('" + word + "'); name one of normal, bias, guillotine, saw");
      }
      partial.style = style;
    }
    partial.reference = ResolveReference();
    const Mention* ratio = Single(reading_.ratios, "quantities");
    const Mention* pieces = Single(reading_.piece_counts, "piece counts");
    if (pieces) {
      if (ratio) {
        Fail("it gives both a ratio ('" + ratio->phrase + "') and a piece count ('" +
             pieces->phrase + "'); a cut is either at one ratio or a split into equal pieces");
      }
      if (reading_.middle) {
        Fail("it asks for both the " + reading_.middle_word + " and a split ('" + pieces->phrase +
             "'); a split already places its cuts");
      }
      partial.state = CutState::kSplit;
      partial.split_pieces = static_cast<int>(pieces->value);
      if (partial.split_pieces < kMinSplitPieces || partial.split_pieces > kMaxSplitPieces) {
        Fail("it asks for " + Format(pieces->value) + " pieces ('" + pieces->phrase +
             "'); a split makes 3, 4 or 5 equal pieces");
      }
    } else if (reading_.split_word) {
      Fail("it asks for a split but not into how many pieces; say e.g. \"into 3 pieces\" "
           "(3, 4 or 5)");
    } else if (ratio) {
      // "half" means ratio 0.5, but "in half at the middle" is still a Middle cut.
      if (reading_.middle && std::abs(ratio->value - 0.5) > kSameValueTolerance) {
        Fail("it asks for both the " + reading_.middle_word + " and ratio " +
             Format(ratio->value) + " ('" + ratio->phrase + "'); give one position");
      }
      partial.state = reading_.middle ? CutState::kMiddle : CutState::kRatio;
      partial.ratio = ratio->value;
      if (!(ratio->value >= kMinRatio - kSameValueTolerance &&
            ratio->value <= kMaxRatio + kSameValueTolerance)) {
        Fail("ratio " + Format(ratio->value) + " ('" + ratio->phrase + "') is outside [" +
             Format(kMinRatio) + ", " + Format(kMaxRatio) +
             "]; a ratio cut lies 0.1 to 0.9 of the length from one end");
      }
    } else if (reading_.ratio_word) {
      Fail("it mentions a ratio but gives no value; say e.g. \"at 0.3 ratio\" or \"at 30%\"");
    } else if (reading_.middle) {
      partial.state = CutState::kMiddle;
    }
    return partial;
  }

  // The one value a list of mentions agrees on; nullptr if none; fails when they differ.
  const Mention* Single(const std::vector<Mention>& mentions, const std::string& what) const {
    for (const Mention& mention : mentions) {
      if (std::abs(mention.value - mentions.front().value) > kSameValueTolerance) {
        Fail("it gives two conflicting " + what + ", '" + mentions.front().phrase + "' (" +
             Format(mentions.front().value) + ") and '" + mention.phrase + "' (" +
             Format(mention.value) + ")");
      }
    }
    return mentions.empty() ? nullptr : &mentions.front();
  }

  std::string text_;
  std::vector<Token> tokens_;
  Reading reading_;
};

}  // namespace

PartialCutSpec ParseInstructionPartial(const std::string& text) { return Parser(text).Parse(); }

CutSpec ParseInstruction(const std::string& text) {
  Parser parser(text);
  const PartialCutSpec partial = parser.Parse();
  if (partial.target_object.empty()) {
    std::string foods;
    for (const std::string& food : KnownFoods()) foods += (foods.empty() ? "" : ", ") + food;
    parser.Fail("it names no food; expected one of: " + foods);
  }
  return ResolveDefaults(partial);
}

}  // namespace culinarycut::task
