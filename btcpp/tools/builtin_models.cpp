// Prints the <TreeNodesModel> of BehaviorTree.CPP's built-in nodes, as its FileLogger2
// writes them into every .btlog. See record-builtin-models.sh.
#include <behaviortree_cpp/bt_factory.h>
#include <behaviortree_cpp/xml_parsing.h>

#include <iostream>

int main()
{
  const BT::BehaviorTreeFactory factory;
  std::cout << BT::writeTreeNodesModelXML(factory, true);
  return 0;
}
