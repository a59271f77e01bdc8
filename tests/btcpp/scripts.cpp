// Runs BehaviorTree.CPP's script engine on the cases of cases/scripts.txt and prints
// what each script returned (or that it failed) and the blackboard after each case:
// the fixture `fixtures/scripts/scripts.txt` that btcpp's script test compares bt-core with.
//
// Input: lines `case NAME`, then `script CODE` lines run in order on one fresh
// blackboard, then `end`. Output: the same lines, each `script` followed by
// `= TYPE VALUE` or `! error`, and before `end` one `key NAME TYPE VALUE` line per
// blackboard entry, sorted by name. Types: int, double, string, empty.
#include <algorithm>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <string>
#include <vector>

#include "behaviortree_cpp/blackboard.h"
#include "behaviortree_cpp/scripting/script_parser.hpp"

static std::string show(const BT::Any& v)
{
  if(v.empty())
  {
    return "empty -";
  }
  if(v.isString())
  {
    return "string '" + v.cast<std::string>() + "'";
  }
  if(v.isType<double>())
  {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.17g", v.cast<double>());
    return std::string("double ") + buf;
  }
  if(v.isIntegral())
  {
    return "int " + std::to_string(v.cast<int64_t>());
  }
  return "other -";
}

int main(int argc, char** argv)
{
  if(argc != 2)
  {
    std::cerr << "usage: scripts CASES\n";
    return 2;
  }
  std::ifstream in(argv[1]);
  std::string line;
  BT::Blackboard::Ptr bb;
  while(std::getline(in, line))
  {
    if(line.rfind("case ", 0) == 0)
    {
      bb = BT::Blackboard::create();
      std::cout << line << "\n";
    }
    else if(line.rfind("script ", 0) == 0)
    {
      std::cout << line << "\n";
      const std::string code = line.substr(7);
      BT::Ast::Environment env{ bb, nullptr };
      auto fn = BT::ParseScript(code);
      if(!fn)
      {
        std::cout << "! error\n";
        continue;
      }
      try
      {
        BT::Any r = fn.value()(env);
        std::cout << "= " << show(r) << "\n";
      }
      catch(const std::exception&)
      {
        std::cout << "! error\n";
      }
    }
    else if(line == "end")
    {
      std::vector<std::string> keys;
      for(const auto& k : bb->getKeys())
      {
        keys.emplace_back(k);
      }
      std::sort(keys.begin(), keys.end());
      for(const auto& k : keys)
      {
        auto entry = bb->getEntry(k);
        std::cout << "key " << k << " " << show(entry->value) << "\n";
      }
      std::cout << "end\n";
    }
  }
  return 0;
}
