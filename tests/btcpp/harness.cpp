// Runs BehaviorTree.CPP on scripted trees and prints what happened, tick by tick.
//
// Input (stdin or the file named by the first argument): cases, each
//
//   case <name>
//   ticks <n>                  ticks to run
//   period <ms>                0: tick at once; else tick k runs at start + k * ms
//   mode <exactly|once>        optional: tickExactlyOnce() (default) or tickOnce(),
//                              which ticks again while a node asks for a wake-up
//   leaf <node> <C|A> <script> one per leaf: its pre-order node id, condition or
//                              action, and the statuses it returns, one per call,
//                              cyclically (S, F, R)
//   spec <tree>                optional, echoed only
//   xml <document on one line>
//   btlog <path>               optional: attach FileLogger2 writing this file
//   end
//
// Leaf types are named after their node: `C7` is the condition at node 7, `A9` the
// action at node 9; the case's `leaf` lines register exactly those types.
//
// Output, per case:
//
//   case <name>
//   <the case's input lines, except btlog and end>
//   tick <k> <root> | <events> | <statuses>
//   ...
//   end
//
// <root> is S, F, R or K (skipped). <events> are, in order: `<node><status>` for a
// leaf call (upper case: the leaf was not Running; lower case: an action that was
// Running and is ticked again), `H<node>` for the halt of a Running action, `h<node>`
// for a halt of an action that was not Running. <statuses> has one character per node
// in pre-order: I, S, F, R (BehaviorTree.CPP's status after the tick). A case that
// BehaviorTree.CPP refuses or that throws prints `error <message>` instead of the
// remaining ticks; one that calls leaves or ticks the root more than 100,000 times in
// a tick prints `runaway`. A case with a period runs twice and prints `error` unless
// every tick came in time and both runs agree.
#include <behaviortree_cpp/bt_factory.h>
#include <behaviortree_cpp/loggers/bt_file_logger_v2.h>

#include <chrono>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <mutex>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

namespace
{

struct Runaway : std::exception
{
  const char* what() const noexcept override { return "runaway"; }
};

// What the leaves did since the last tick was printed: Timeout's timer halts its child
// from another thread, between ticks, so such a halt opens the next tick's events.
struct Log
{
  std::mutex mutex;
  std::string events;
  long calls = 0;

  void add(const std::string& e)
  {
    const std::lock_guard<std::mutex> lock(mutex);
    if(!events.empty())
    {
      events += ' ';
    }
    events += e;
  }
  std::string take()
  {
    const std::lock_guard<std::mutex> lock(mutex);
    std::string out;
    out.swap(events);
    return out;
  }
  void call()
  {
    if(++calls > 100000)
    {
      throw Runaway();
    }
  }
};

BT::NodeStatus parse(char c)
{
  switch(c)
  {
    case 'S':
      return BT::NodeStatus::SUCCESS;
    case 'F':
      return BT::NodeStatus::FAILURE;
    default:
      return BT::NodeStatus::RUNNING;
  }
}

char letter(BT::NodeStatus s)
{
  switch(s)
  {
    case BT::NodeStatus::SUCCESS:
      return 'S';
    case BT::NodeStatus::FAILURE:
      return 'F';
    case BT::NodeStatus::RUNNING:
      return 'R';
    case BT::NodeStatus::SKIPPED:
      return 'K';
    default:
      return 'I';
  }
}

struct Leaf
{
  int node = 0;
  std::string script;
  size_t calls = 0;

  BT::NodeStatus next()
  {
    const char c = script[calls % script.size()];
    calls++;
    return parse(c);
  }
};

class ScriptedCondition : public BT::ConditionNode
{
public:
  ScriptedCondition(const std::string& name, const BT::NodeConfig& config,
                    std::shared_ptr<Leaf> leaf, Log* log)
    : BT::ConditionNode(name, config), leaf_(std::move(leaf)), log_(log)
  {}
  static BT::PortsList providedPorts() { return {}; }

  BT::NodeStatus tick() override
  {
    log_->call();
    const BT::NodeStatus s = leaf_->next();
    log_->add(std::to_string(leaf_->node) + letter(s));
    return s;
  }

private:
  std::shared_ptr<Leaf> leaf_;
  Log* log_;
};

class ScriptedAction : public BT::ActionNodeBase
{
public:
  ScriptedAction(const std::string& name, const BT::NodeConfig& config,
                 std::shared_ptr<Leaf> leaf, Log* log)
    : BT::ActionNodeBase(name, config), leaf_(std::move(leaf)), log_(log)
  {}
  static BT::PortsList providedPorts() { return {}; }

  BT::NodeStatus tick() override
  {
    log_->call();
    const bool running = status() == BT::NodeStatus::RUNNING;
    const BT::NodeStatus s = leaf_->next();
    char c = letter(s);
    if(running)
    {
      c = char(c - 'A' + 'a');
    }
    log_->add(std::to_string(leaf_->node) + c);
    return s;
  }

  // As BT::StatefulActionNode's halt(): Idle again. A parent resets a halted child
  // anyway; a node that `_while` halts itself is reset only here.
  void halt() override
  {
    const bool running = status() == BT::NodeStatus::RUNNING;
    log_->add((running ? "H" : "h") + std::to_string(leaf_->node));
    resetStatus();
  }

private:
  std::shared_ptr<Leaf> leaf_;
  Log* log_;
};

struct Case
{
  std::string name;
  int ticks = 0;
  int period_ms = 0;
  bool once = false;
  std::vector<std::pair<char, std::shared_ptr<Leaf>>> leaves;
  std::string xml;
  std::string btlog;
  std::vector<std::string> echo;  // the input lines, repeated in the output
};

// The ticks of one run of a case (after its echoed input lines).
void ticks(const Case& c, const std::string& btlog, std::ostream& out)
{
  for(const auto& [kind, leaf] : c.leaves)
  {
    leaf->calls = 0;
  }
  Log log;
  BT::BehaviorTreeFactory factory;
  for(const auto& [kind, leaf] : c.leaves)
  {
    const std::string id = std::string(1, kind) + std::to_string(leaf->node);
    if(kind == 'C')
    {
      factory.registerNodeType<ScriptedCondition>(id, leaf, &log);
    }
    else
    {
      factory.registerNodeType<ScriptedAction>(id, leaf, &log);
    }
  }
  try
  {
    BT::Tree tree = factory.createTreeFromText(c.xml);
    std::vector<const BT::TreeNode*> order;
    BT::applyRecursiveVisitor(static_cast<const BT::TreeNode*>(tree.rootNode()),
                              [&](const BT::TreeNode* n) { order.push_back(n); });
    // tickOnce() ticks the root again while a node asks for a wake-up: a Repeat of -1
    // over a child that always succeeds at once never stops. Count the root's ticks.
    tree.rootNode()->setPreTickFunction([&log](BT::TreeNode&) {
      log.call();
      return BT::NodeStatus::IDLE;
    });
    std::unique_ptr<BT::FileLogger2> logger;
    if(!btlog.empty())
    {
      logger = std::make_unique<BT::FileLogger2>(tree, btlog);
    }
    const auto start = std::chrono::steady_clock::now();
    for(int k = 0; k < c.ticks; k++)
    {
      if(c.period_ms > 0)
      {
        const auto due = start + std::chrono::milliseconds(k * c.period_ms);
        std::this_thread::sleep_until(due);
        // Timers expire half a period from a tick: a tick a quarter late is unsafe.
        if(std::chrono::steady_clock::now() - due > std::chrono::milliseconds(c.period_ms / 4))
        {
          out << "error tick " << k << " came late\n";
          break;
        }
      }
      log.calls = 0;
      BT::NodeStatus root;
      try
      {
        root = c.once ? tree.tickOnce() : tree.tickExactlyOnce();
      }
      catch(const Runaway&)
      {
        out << "runaway\n";
        break;
      }
      std::string statuses;
      for(const auto* n : order)
      {
        statuses += letter(n->status());
      }
      out << "tick " << k << ' ' << letter(root) << " | " << log.take() << " | "
          << statuses << '\n';
    }
    if(logger)
    {
      // FileLogger2's writer thread drains its queue every 10 ms and stops without a
      // last drain: give it time to write every transition before the logger goes.
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
      logger->flush();
    }
  }
  catch(const std::exception& e)
  {
    std::string msg = e.what();
    for(auto& ch : msg)
    {
      if(ch == '\n')
      {
        ch = ' ';
      }
    }
    out << "error " << msg << '\n';
  }
}

void run(const Case& c, std::ostream& out)
{
  out << "case " << c.name << '\n';
  for(const auto& line : c.echo)
  {
    out << line << '\n';
  }
  std::ostringstream first;
  ticks(c, c.btlog, first);
  if(c.period_ms > 0)
  {
    // A clocked case runs twice: both runs must agree, or the timing was not safe.
    std::ostringstream second;
    ticks(c, "", second);
    if(second.str() != first.str())
    {
      if(std::getenv("HARNESS_DEBUG") != nullptr)
      {
        std::cerr << first.str() << "---\n" << second.str();
      }
      out << "error the two runs differ: timing was not reliable\n";
      out << "end\n";
      return;
    }
  }
  out << first.str() << "end\n";
}

}  // namespace

int main(int argc, char** argv)
{
  std::ifstream file;
  std::istream* in = &std::cin;
  if(argc > 1)
  {
    file.open(argv[1]);
    if(!file)
    {
      std::cerr << "cannot open " << argv[1] << '\n';
      return 2;
    }
    in = &file;
  }
  std::string line;
  Case c;
  while(std::getline(*in, line))
  {
    std::istringstream words(line);
    std::string key;
    words >> key;
    if(key != "case" && key != "end" && key != "btlog" && !key.empty())
    {
      c.echo.push_back(line);
    }
    if(key == "case")
    {
      c = Case();
      words >> c.name;
    }
    else if(key == "ticks")
    {
      words >> c.ticks;
    }
    else if(key == "period")
    {
      words >> c.period_ms;
    }
    else if(key == "leaf")
    {
      auto leaf = std::make_shared<Leaf>();
      char kind = 0;
      words >> leaf->node >> kind >> leaf->script;
      c.leaves.emplace_back(kind, leaf);
    }
    else if(key == "xml")
    {
      c.xml = line.substr(4);
    }
    else if(key == "mode")
    {
      std::string mode;
      words >> mode;
      c.once = mode == "once";
    }
    else if(key == "spec")
    {
      // echoed only: the tree in the test's own notation
    }
    else if(key == "btlog")
    {
      words >> c.btlog;
    }
    else if(key == "end")
    {
      run(c, std::cout);
      std::cout.flush();
    }
    else if(!key.empty())
    {
      std::cerr << "unknown line: " << line << '\n';
      return 2;
    }
  }
  return 0;
}
