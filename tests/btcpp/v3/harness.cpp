// Runs BehaviorTree.CPP 3.8 on scripted v3 documents and prints what happened, tick by
// tick: the v3 counterpart of ../harness.cpp (see ../README.md).
//
// Input (stdin or the file named by the first argument): cases, each
//
//   case <name>
//   ticks <n>                  ticks to run (tickRoot(), once each)
//   period <ms>                0: tick at once; else tick k runs at start + k * ms
//   leaf <type> <C|A> <script> one per leaf type: condition or action, and the
//                              statuses it returns, one per call of any node of the
//                              type, cyclically (S, F, R)
//   xml <document on one line>
//   end
//
// Every leaf type has an input port `in` and an output port `out` (both int). A leaf
// reads `in` when ticked, then writes `out` = 1000 * (the number in its type's name) +
// the type's call count, then returns the next status of its script.
//
// Output, per case:
//
//   case <name>
//   <the case's input lines, except end>
//   nodes <ID>/<parent> ...     every node in pre-order: registration ID (a SubTree
//                               node: SubTree), parent's pre-order index (- for the root)
//   tick <k> <root> | <events> | <statuses>
//   ...
//   end
//
// <events> in order: `<node><status>:<in>` for a leaf call (node: pre-order index;
// status upper case when the leaf was not Running, lower case for an action that was
// Running and is ticked again; <in>: the integer its `in` port gave, or `-` when the
// port gave none), `H<node>` for the halt of a Running action, `h<node>` for a halt of
// an action that was not Running. <statuses>: one letter per node in pre-order, I, S,
// F, R. A case BehaviorTree.CPP refuses or that throws prints `error <message>` instead
// of the remaining ticks; one that ticks nodes more than 100,000 times in a tick (a
// Repeat of -1 whose child never stops) prints `runaway`. A case with a period runs twice and prints `error` unless
// every tick came in time and both runs agree.
#include <behaviortree_cpp_v3/bt_factory.h>

#include <atomic>
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
  std::map<const BT::TreeNode*, int> index;  // pre-order index of every node
  std::atomic<long> calls{0};                // status changes in this tick

  void call()
  {
    if(++calls > 100000)
    {
      throw Runaway();
    }
  }

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
  int of(const BT::TreeNode* n)
  {
    auto it = index.find(n);
    return it == index.end() ? -1 : it->second;
  }
};

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
    default:
      return 'I';
  }
}

struct Type
{
  int number = 0;
  std::string script;
  size_t calls = 0;

  BT::NodeStatus next()
  {
    const char c = script[calls % script.size()];
    calls++;
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
};

BT::PortsList leafPorts()
{
  return {BT::InputPort<int>("in"), BT::OutputPort<int>("out")};
}

// Reads `in`, writes `out`, takes the next status: the event without its status letter.
template <class Node>
BT::NodeStatus step(Node& node, Type& type, std::string& read)
{

  const BT::Optional<int> in = node.template getInput<int>("in");
  read = in ? std::to_string(in.value()) : std::string("-");
  const BT::NodeStatus s = type.next();
  node.setOutput("out", type.number * 1000 + int(type.calls));
  return s;
}

class ScriptedCondition : public BT::ConditionNode
{
public:
  ScriptedCondition(const std::string& name, const BT::NodeConfiguration& config,
                    std::shared_ptr<Type> type, Log* log)
    : BT::ConditionNode(name, config), type_(std::move(type)), log_(log)
  {}
  static BT::PortsList providedPorts() { return leafPorts(); }

  BT::NodeStatus tick() override
  {
    std::string read;
    const BT::NodeStatus s = step(*this, *type_, read);
    log_->add(std::to_string(log_->of(this)) + letter(s) + ":" + read);
    return s;
  }

private:
  std::shared_ptr<Type> type_;
  Log* log_;
};

class ScriptedAction : public BT::ActionNodeBase
{
public:
  ScriptedAction(const std::string& name, const BT::NodeConfiguration& config,
                 std::shared_ptr<Type> type, Log* log)
    : BT::ActionNodeBase(name, config), type_(std::move(type)), log_(log)
  {}
  static BT::PortsList providedPorts() { return leafPorts(); }

  BT::NodeStatus tick() override
  {
    const bool running = status() == BT::NodeStatus::RUNNING;
    std::string read;
    const BT::NodeStatus s = step(*this, *type_, read);
    char c = letter(s);
    if(running)
    {
      c = char(c - 'A' + 'a');
    }
    log_->add(std::to_string(log_->of(this)) + c + ":" + read);
    return s;
  }

  void halt() override
  {
    const bool running = status() == BT::NodeStatus::RUNNING;
    log_->add((running ? "H" : "h") + std::to_string(log_->of(this)));
    setStatus(BT::NodeStatus::IDLE);
  }

private:
  std::shared_ptr<Type> type_;
  Log* log_;
};

struct Case
{
  std::string name;
  int ticks = 0;
  int period_ms = 0;
  std::vector<std::pair<char, std::shared_ptr<Type>>> types;
  std::vector<std::string> names;
  std::string xml;
  std::vector<std::string> echo;
};

// Pre-order, with each node's parent.
void visit(const BT::TreeNode* n, int parent, std::vector<std::pair<const BT::TreeNode*, int>>& out)
{
  const int me = int(out.size());
  out.emplace_back(n, parent);
  if(auto control = dynamic_cast<const BT::ControlNode*>(n))
  {
    for(const auto* c : control->children())
    {
      visit(c, me, out);
    }
  }
  else if(auto decorator = dynamic_cast<const BT::DecoratorNode*>(n))
  {
    if(decorator->child() != nullptr)
    {
      visit(decorator->child(), me, out);
    }
  }
}

void ticks(const Case& c, std::ostream& out, bool print_nodes)
{
  for(const auto& [kind, type] : c.types)
  {
    type->calls = 0;
  }
  Log log;
  BT::BehaviorTreeFactory factory;
  for(size_t i = 0; i < c.types.size(); i++)
  {
    const auto& [kind, type] = c.types[i];
    const std::string id = c.names[i];
    Log* lp = &log;
    auto t = type;
    if(kind == 'C')
    {
      factory.registerBuilder<ScriptedCondition>(
          id, [t, lp](const std::string& name, const BT::NodeConfiguration& config) {
            return std::make_unique<ScriptedCondition>(name, config, t, lp);
          });
    }
    else
    {
      factory.registerBuilder<ScriptedAction>(
          id, [t, lp](const std::string& name, const BT::NodeConfiguration& config) {
            return std::make_unique<ScriptedAction>(name, config, t, lp);
          });
    }
  }
  try
  {
    BT::Tree tree = factory.createTreeFromText(c.xml);
    std::vector<std::pair<const BT::TreeNode*, int>> order;
    visit(tree.rootNode(), -1, order);
    std::vector<BT::TreeNode::StatusChangeSubscriber> subscribers;
    for(size_t i = 0; i < order.size(); i++)
    {
      log.index[order[i].first] = int(i);
      // Every status change counts towards a runaway (a Repeat of -1 over a child that
      // always succeeds at once never returns). 3.8 declares but does not define the
      // post-tick hook, and skips tick() whenever a pre-tick one is set.
      Log* lp = &log;
      subscribers.push_back(const_cast<BT::TreeNode*>(order[i].first)
                                ->subscribeToStatusChange([lp](BT::TimePoint, const BT::TreeNode&,
                                                               BT::NodeStatus, BT::NodeStatus) { lp->call(); }));
    }
    if(print_nodes)
    {
      out << "nodes";
      for(const auto& [n, parent] : order)
      {
        const std::string id = n->type() == BT::NodeType::SUBTREE ? "SubTree" : n->registrationName();
        out << ' ' << id << '/' << (parent < 0 ? std::string("-") : std::to_string(parent));
      }
      out << '\n';
    }
    const auto start = std::chrono::steady_clock::now();
    for(int k = 0; k < c.ticks; k++)
    {
      if(c.period_ms > 0)
      {
        const auto due = start + std::chrono::milliseconds(k * c.period_ms);
        std::this_thread::sleep_until(due);
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
        root = tree.tickRoot();
      }
      catch(const Runaway&)
      {
        out << "runaway\n";
        break;
      }
      std::string statuses;
      for(const auto& [n, parent] : order)
      {
        statuses += letter(n->status());
      }
      out << "tick " << k << ' ' << letter(root) << " | " << log.take() << " | " << statuses
          << '\n';
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
  ticks(c, first, true);
  if(c.period_ms > 0)
  {
    std::ostringstream second;
    ticks(c, second, true);
    if(second.str() != first.str())
    {
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
  // BehaviorTree.CPP 3.8 prints blackboard dumps to std::cout before some throws: the
  // results go to stdout through a stream of their own, std::cout goes nowhere.
  std::ostream results(std::cout.rdbuf());
  std::cout.rdbuf(nullptr);
  std::string line;
  Case c;
  while(std::getline(*in, line))
  {
    std::istringstream words(line);
    std::string key;
    words >> key;
    if(key != "case" && key != "end" && !key.empty())
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
      auto type = std::make_shared<Type>();
      std::string name;
      char kind = 0;
      words >> name >> kind >> type->script;
      type->number = std::atoi(name.c_str() + 1);
      c.types.emplace_back(kind, type);
      c.names.push_back(name);
    }
    else if(key == "xml")
    {
      c.xml = line.substr(4);
    }
    else if(key == "end")
    {
      run(c, results);
      results.flush();
    }
    else if(!key.empty())
    {
      std::cerr << "unknown line: " << line << '\n';
      return 2;
    }
  }
  return 0;
}
