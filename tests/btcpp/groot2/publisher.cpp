// A tree with scripted leaves under BehaviorTree.CPP's Groot2Publisher, ticked on
// command, for record.py to question as Groot2 does (see record.sh).
//
//   publisher TREE.xml PORT
//
// Prints `ready` once the publisher listens on PORT (and PORT + 1), then reads
// commands from stdin, one a line:
//   tick  ticks the tree once (tickExactlyOnce) and prints every status change it
//         made, `change UID PREV NEW` (BehaviorTree.CPP's status numbers), then
//         `ticked STATUS`
//   quit  ends.
// Each leaf returns its script, cyclically: a string of S, F and R per leaf ID below.
// Actions are StatefulActionNodes (Idle again once halted), conditions return S or F.
#include <behaviortree_cpp/bt_factory.h>
#include <behaviortree_cpp/loggers/groot2_publisher.h>

#include <cstdio>
#include <iostream>
#include <map>
#include <string>

namespace
{
const std::map<std::string, std::string> kScripts = {
  { "BatteryOk", "SSSSSSFSSSSS" },
  { "DoorOpen", "FFFSSSSSFFFF" },
  { "OpenDoor", "RRS" },
  { "PickCube", "RSRRS" },
  { "PlaceCube", "RRRF" },
};

BT::NodeStatus next(const std::string& id, size_t& k)
{
  const std::string& s = kScripts.at(id);
  const char c = s[k++ % s.size()];
  return c == 'S' ? BT::NodeStatus::SUCCESS :
         c == 'F' ? BT::NodeStatus::FAILURE :
                    BT::NodeStatus::RUNNING;
}

class Scripted : public BT::StatefulActionNode
{
public:
  Scripted(const std::string& name, const BT::NodeConfig& config)
    : BT::StatefulActionNode(name, config)
  {}
  static BT::PortsList providedPorts()
  {
    return {};
  }
  BT::NodeStatus onStart() override
  {
    return next(registrationName(), calls_);
  }
  BT::NodeStatus onRunning() override
  {
    return next(registrationName(), calls_);
  }
  void onHalted() override
  {}

private:
  size_t calls_ = 0;
};

class Printer : public BT::StatusChangeLogger
{
public:
  explicit Printer(BT::TreeNode* root) : BT::StatusChangeLogger(root)
  {}
  void callback(BT::Duration, const BT::TreeNode& node, BT::NodeStatus prev,
                BT::NodeStatus status) override
  {
    std::printf("change %u %d %d\n", unsigned(node.UID()), int(prev), int(status));
  }
  void flush() override
  {}
};
}  // namespace

int main(int argc, char** argv)
{
  if(argc != 3)
  {
    std::fprintf(stderr, "usage: publisher TREE.xml PORT\n");
    return 2;
  }
  BT::BehaviorTreeFactory factory;
  for(const auto& [id, script] : kScripts)
  {
    if(id == "BatteryOk" || id == "DoorOpen")
    {
      auto k = std::make_shared<size_t>(0);
      factory.registerSimpleCondition(
          id, [id = id, k](BT::TreeNode&) { return next(id, *k); });
    }
    else
    {
      factory.registerNodeType<Scripted>(id);
    }
  }
  auto tree = factory.createTreeFromFile(argv[1]);
  BT::Groot2Publisher publisher(tree, unsigned(std::stoi(argv[2])));
  Printer printer(tree.rootNode());
  std::printf("ready\n");
  std::fflush(stdout);
  std::string line;
  while(std::getline(std::cin, line))
  {
    if(line == "tick")
    {
      const auto status = tree.tickExactlyOnce();
      std::printf("ticked %d\n", int(status));
      std::fflush(stdout);
    }
    else if(line == "quit")
    {
      break;
    }
  }
  return 0;
}
