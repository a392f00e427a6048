#include "compiler/backend/llvm/LlvmJit.h"

#include "compiler/backend/llvm/LlvmTranslate.h"
#include "compiler/diag/Diagnostics.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <fmt/format.h>
#include <llvm/Analysis/TargetLibraryInfo.h>
#include <llvm/Analysis/TargetTransformInfo.h>
#include <llvm/Config/llvm-config.h>
#include <llvm/ExecutionEngine/Orc/CompileUtils.h>
#include <llvm/ExecutionEngine/Orc/ExecutionUtils.h>
#include <llvm/ExecutionEngine/Orc/JITTargetMachineBuilder.h>
#include <llvm/ExecutionEngine/Orc/LLJIT.h>
#include <llvm/ExecutionEngine/Orc/ThreadSafeModule.h>
#include <llvm/IR/LegacyPassManager.h>
#include <llvm/Object/ObjectFile.h>
#include <llvm/Passes/PassBuilder.h>
#include <llvm/Support/DynamicLibrary.h>
#include <llvm/Support/raw_ostream.h>
#include <llvm/Support/TargetSelect.h>
#include <llvm/Target/TargetMachine.h>
#include <llvm/TargetParser/Host.h>
#include <mutex>
#include <optional>
#include <thread>
#include <unordered_map>

namespace moire {

namespace {

void initialiseLlvmOnce() {
    static std::once_flag once;
    std::call_once(once, [] {
        llvm::InitializeNativeTarget();
        llvm::InitializeNativeTargetAsmPrinter();
        llvm::InitializeNativeTargetAsmParser();
    });
}

std::string errorText(llvm::Error e) {
    std::string s;
    llvm::raw_string_ostream os(s);
    os << e;
    return os.str();
}

// glibc's vector maths library (libmvec): 4-lane (SSE), 8-lane (AVX2) and 16-lane (AVX-512)
// versions of the libm functions kernels call, for the translation in lanes and for the loop
// vectoriser of scalar code (4 and 8 lanes). Accuracy: within 4 ulp, where the scalar
// functions are within 1.
constexpr const char* kLibmvec[][4] = {
    // scalar, 4 lanes, 8 lanes, 16 lanes (AVX-512; used by the translation in lanes only)
    {"sinf", "_ZGVbN4v_sinf", "_ZGVdN8v_sinf", "_ZGVeN16v_sinf"},
    {"cosf", "_ZGVbN4v_cosf", "_ZGVdN8v_cosf", "_ZGVeN16v_cosf"},
    {"tanf", "_ZGVbN4v_tanf", "_ZGVdN8v_tanf", "_ZGVeN16v_tanf"},
    {"asinf", "_ZGVbN4v_asinf", "_ZGVdN8v_asinf", "_ZGVeN16v_asinf"},
    {"acosf", "_ZGVbN4v_acosf", "_ZGVdN8v_acosf", "_ZGVeN16v_acosf"},
    {"atanf", "_ZGVbN4v_atanf", "_ZGVdN8v_atanf", "_ZGVeN16v_atanf"},
    {"atan2f", "_ZGVbN4vv_atan2f", "_ZGVdN8vv_atan2f", "_ZGVeN16vv_atan2f"},
    {"expf", "_ZGVbN4v_expf", "_ZGVdN8v_expf", "_ZGVeN16v_expf"},
    {"logf", "_ZGVbN4v_logf", "_ZGVdN8v_logf", "_ZGVeN16v_logf"},
    {"powf", "_ZGVbN4vv_powf", "_ZGVdN8vv_powf", "_ZGVeN16vv_powf"},
};

// Loads libmvec into the process once; false where it is missing (kernels stay scalar).
bool libmvecAvailable() {
    static const bool loaded = [] {
        std::string err;
        if (llvm::sys::DynamicLibrary::LoadLibraryPermanently("libmvec.so.1", &err)) return false;
        for (const auto& f : kLibmvec)
            for (int w = 1; w < 4; ++w)
                if (!llvm::sys::DynamicLibrary::SearchForAddressOfSymbol(f[w])) return false;
        return true;
    }();
    return loaded;
}

// What a kernel translated in lanes needs, and no more. Its code arrives nearly in final
// form: every op already a vector instruction, no calls to inline, no loop to vectorise.
// What is left: promote the output slots' allocas to registers (SROA), fold the
// translation's redundancies (CSE, instcombine, CFG clean-up), and hoist what depends only on
// uniforms out of the pixel loop and the solver's loops (LICM), which is most of a walking
// kernel's set-up. The order follows LLVM's own function simplification pipeline.
//
// Given as text for LLVM's parser, not built from pass classes here: instantiating LLVM's
// pass templates in moire's binary exports them, and a second LLVM in the process (Mesa's
// OpenGL, in `moire view`) would then bind its own passes to these, of another version.
constexpr const char* kLeanPipeline =
    "function(sroa<modify-cfg>,early-cse,instcombine,simplifycfg,loop-mssa(licm),early-cse,"
    "instcombine,simplifycfg)";

// The optimisation pipeline, for the host CPU (LlvmJitBackend::Pipeline).
void optimise(llvm::Module& m, llvm::TargetMachine& tm, LlvmJitBackend::Pipeline pipeline) {
    llvm::LoopAnalysisManager lam;
    llvm::FunctionAnalysisManager fam;
    llvm::CGSCCAnalysisManager cgam;
    llvm::ModuleAnalysisManager mam;
    llvm::TargetLibraryInfoImpl tlii(tm.getTargetTriple());
    std::vector<llvm::VecDesc> vecFns;
    if (libmvecAvailable() && tm.getTargetTriple().isX86()) {
        for (const auto& f : kLibmvec) {
            vecFns.push_back({f[0], f[1], llvm::ElementCount::getFixed(4)});
            vecFns.push_back({f[0], f[2], llvm::ElementCount::getFixed(8)});
        }
        tlii.addVectorizableFunctions(vecFns);
    }
    // Registered before the defaults, so this library info is the one the passes see.
    fam.registerPass([&] { return llvm::TargetLibraryAnalysis(tlii); });
    llvm::PassBuilder pb(&tm);
    pb.registerModuleAnalyses(mam);
    pb.registerCGSCCAnalyses(cgam);
    pb.registerFunctionAnalyses(fam);
    pb.registerLoopAnalyses(lam);
    pb.crossRegisterProxies(lam, fam, cgam, mam);
    llvm::ModulePassManager mpm;
    switch (pipeline) {
    case LlvmJitBackend::Pipeline::Auto: // resolved by the backend before this point
    case LlvmJitBackend::Pipeline::O2:
        mpm = pb.buildPerModuleDefaultPipeline(llvm::OptimizationLevel::O2);
        break;
    case LlvmJitBackend::Pipeline::O1:
        mpm = pb.buildPerModuleDefaultPipeline(llvm::OptimizationLevel::O1);
        break;
    case LlvmJitBackend::Pipeline::Lean:
        if (auto err = pb.parsePassPipeline(mpm, kLeanPipeline))
            MOIRE_ICE("LLVM rejected the lean pipeline: {}", errorText(std::move(err)));
        break;
    }
    mpm.run(m, mam);
}

// Floats in the target's widest vector register, as the loop vectoriser counts it (an x86
// tuned to prefer 256-bit vectors says 256 even with AVX-512). For a pixel loop of float
// arithmetic, the width its cost model settles on.
unsigned widestFloatVector(llvm::TargetMachine& tm) {
    llvm::LLVMContext ctx;
    llvm::Module m("probe", ctx);
    auto* fn = llvm::Function::Create(llvm::FunctionType::get(llvm::Type::getVoidTy(ctx), false),
                                      llvm::Function::ExternalLinkage, "probe", m);
    llvm::TargetTransformInfo tti = tm.getTargetTransformInfo(*fn);
    auto bits = tti.getRegisterBitWidth(llvm::TargetTransformInfo::RGK_FixedWidthVector);
    return std::max<unsigned>(1, static_cast<unsigned>(bits.getFixedValue() / 32));
}

// Pixels per step where the options leave it to the host: the floats of its widest vector
// register as LLVM's cost model counts it (16 with AVX-512 unless the CPU is tuned to prefer
// 256-bit vectors, 8 with AVX2, 4 with SSE or NEON), the width the loop vectoriser picks for
// straight-line kernels too; libmvec has functions of each of these widths.
unsigned hostLanes(llvm::TargetMachine& tm) {
    unsigned widest = widestFloatVector(tm);
    return widest >= 16 ? 16 : widest >= 8 ? 8 : 4;
}

// FNV-1a: a hash that is the same in every build, for keys kept on disk.
uint64_t fnv1a(std::string_view text) {
    uint64_t h = 0xcbf29ce484222325ull;
    for (unsigned char c : text) h = (h ^ c) * 0x100000001b3ull;
    return h;
}

class JitKernel : public CompiledKernel {
  public:
    JitKernel(llvmbackend::TileFn fn, int numOutputs) : fn_(fn), numOutputs_(numOutputs) {}
    int numOutputs() const override { return numOutputs_; }
    void runTile(const KernelFrame& frame, TileRect t, float* out,
                 size_t rowStride) const override {
        fn_(frame.uniforms, frame.imageW, frame.imageH, t.x0, t.y0, t.x1, t.y1, out,
            static_cast<int64_t>(rowStride));
    }

  private:
    llvmbackend::TileFn fn_;
    int numOutputs_;
};

} // namespace

struct LlvmJitBackend::Impl {
    std::unique_ptr<llvm::orc::LLJIT> jit;
    std::optional<llvm::orc::JITTargetMachineBuilder> jtmb;
    // The backend's target machine, which also compiles on the calling thread; and one for
    // each further compiling thread (a TargetMachine is not safe to share between threads).
    std::unique_ptr<llvm::TargetMachine> tm;
    std::vector<std::unique_ptr<llvm::TargetMachine>> workerMachines;
    std::mutex mutex;
    std::unordered_map<uint64_t, llvmbackend::TileFn> cache;
    int compiled = 0;
    Options options;
    unsigned chunkVectorWidth = 0;
    unsigned lanes = 1;
    bool vectorMaths = false;

    explicit Impl(const Options& o) : options(o) {
        initialiseLlvmOnce();
        auto detected = llvm::orc::JITTargetMachineBuilder::detectHost();
        if (!detected)
            MOIRE_ICE("LLVM cannot target this host: {}", errorText(detected.takeError()));
        jtmb = std::move(*detected);
        jtmb->setCodeGenOptLevel(options.codegenLess ? llvm::CodeGenOpt::Less
                                                     : llvm::CodeGenOpt::Default);
        tm = targetMachine();
        chunkVectorWidth = options.chunkVectorWidth == Options::kWidestFloatVector
                               ? widestFloatVector(*tm)
                               : static_cast<unsigned>(std::max(0, options.chunkVectorWidth));
        lanes = options.lanes == Options::kHostLanes ? hostLanes(*tm)
                                                     : static_cast<unsigned>(options.lanes);
        if (lanes != 1 && lanes != 4 && lanes != 8 && lanes != 16)
            MOIRE_ICE("the JIT runs 1, 4, 8 or 16 lanes, not {}", options.lanes);
        vectorMaths = tm->getTargetTriple().isX86() && libmvecAvailable() &&
                      (lanes != 16 || tm->getTargetFeatureString().contains("+avx512f"));
        codeConfig = fnv1a(fmt::format("{}|{}|{}|{}|{}|{}|{}|{}|{}|{}|{}", LLVM_VERSION_STRING,
                                       tm->getTargetCPU().str(), tm->getTargetFeatureString().str(),
                                       options.chunkInsts, chunkVectorWidth, options.classicChunks,
                                       lanes, vectorMaths, static_cast<int>(pipeline()),
                                       options.codegenLess, options.outlineInsts));
        auto built = llvm::orc::LLJITBuilder().setJITTargetMachineBuilder(*jtmb).create();
        if (!built) MOIRE_ICE("cannot start the LLVM JIT: {}", errorText(built.takeError()));
        jit = std::move(*built);
        // Kernels call libm (sinf, atan2f, ...) from this process.
        auto gen = llvm::orc::DynamicLibrarySearchGenerator::GetForCurrentProcess(
            jit->getDataLayout().getGlobalPrefix());
        if (!gen) MOIRE_ICE("LLVM symbol generator: {}", errorText(gen.takeError()));
        jit->getMainJITDylib().addGenerator(std::move(*gen));
    }

    // One per compiling thread: a TargetMachine is not safe to share between threads.
    std::unique_ptr<llvm::TargetMachine> targetMachine() {
        auto tmOr = jtmb->createTargetMachine();
        if (!tmOr) MOIRE_ICE("LLVM target machine: {}", errorText(tmOr.takeError()));
        return std::move(*tmOr);
    }

    std::vector<llvmbackend::OwnedModule> translate(const ir::Function& kernel,
                                                    const std::string& name) {
        llvmbackend::TranslateOptions t;
        t.chunkInsts = options.chunkInsts;
        t.wholeStrips = t.separateModules = !options.classicChunks;
        t.chunkVectorWidth = chunkVectorWidth;
        t.lanes = lanes;
        t.vectorMaths = vectorMaths;
        t.outlineInsts = options.outlineInsts;
        return llvmbackend::translate(kernel, name, t);
    }

    // The lean pipeline is for code in lanes; scalar code needs the vectoriser (-O2).
    LlvmJitBackend::Pipeline pipeline() const {
        if (options.pipeline != Pipeline::Auto) return options.pipeline;
        return lanes > 1 ? Pipeline::Lean : Pipeline::O2;
    }

    void prepare(llvm::Module& m, llvm::TargetMachine& machine) {
        m.setDataLayout(jit->getDataLayout());
        m.setTargetTriple(machine.getTargetTriple().str());
        optimise(m, machine, pipeline());
    }

    // The name a module's object code is kept under: the module's name (the kernel's
    // structural hash, and the chunk) and a hash of everything else its code depends on.
    std::string objectKey(const llvm::Module& m) const {
        return fmt::format("{}-{:016x}", m.getModuleIdentifier(), codeConfig);
    }

    // Optimises and compiles a kernel's modules to object code (on several threads when it
    // was chunked: LLVM's time for a kernel of 1,000 layers is seconds, and the chunks are
    // independent), or takes it from the object store, then hands the objects to the JIT.
    void compileModules(std::vector<llvmbackend::OwnedModule>& modules) {
        unsigned threads = options.compileThreads > 0
                               ? static_cast<unsigned>(options.compileThreads)
                               : std::max(1u, std::thread::hardware_concurrency());
        threads = std::min<unsigned>(threads, static_cast<unsigned>(modules.size()));
        std::vector<std::string> keys;
        for (auto& m : modules) keys.push_back(objectKey(*m.module));
        std::vector<std::unique_ptr<llvm::MemoryBuffer>> objects(modules.size());
        std::vector<std::string> errors(modules.size());
        std::vector<char> compiled(modules.size(), 0);
        ObjectStore* store = options.objects.get();
        // Largest first: the threads then finish close together (LLVM's time for a module
        // grows with its instructions).
        std::vector<size_t> order(modules.size()), size(modules.size(), 0);
        for (size_t i = 0; i < modules.size(); ++i) {
            order[i] = i;
            for (const llvm::Function& fn : *modules[i].module) size[i] += fn.getInstructionCount();
        }
        std::stable_sort(order.begin(), order.end(),
                         [&](size_t a, size_t b) { return size[a] > size[b]; });
        std::atomic<size_t> next{0};
        auto work = [&](llvm::TargetMachine& machine) {
            llvm::orc::SimpleCompiler compile(machine);
            for (size_t n; (n = next++) < modules.size();) {
                const size_t i = order[n];
                if (store) {
                    if (auto object = loadObject(*store, keys[i])) {
                        objects[i] = std::move(object);
                        ++hits;
                        continue;
                    }
                }
                auto t0 = std::chrono::steady_clock::now();
                prepare(*modules[i].module, machine);
                auto t1 = std::chrono::steady_clock::now();
                auto object = compile(*modules[i].module);
                auto t2 = std::chrono::steady_clock::now();
                optimiseNs += std::chrono::nanoseconds(t1 - t0).count();
                codegenNs += std::chrono::nanoseconds(t2 - t1).count();
                if (object) {
                    objects[i] = std::move(*object);
                    compiled[i] = 1;
                } else {
                    errors[i] = errorText(object.takeError());
                }
            }
        };
        // Target machines are made here (MOIRE_ICE must not throw on a worker thread) and kept
        // for the next kernel: each builds its subtarget's tables on first use.
        while (workerMachines.size() + 1 < threads) workerMachines.push_back(targetMachine());
        std::vector<std::thread> workers;
        for (unsigned t = 1; t < threads; ++t)
            workers.emplace_back(work, std::ref(*workerMachines[t - 1]));
        work(*tm);
        for (std::thread& w : workers) w.join();
        for (size_t i = 0; i < modules.size(); ++i) {
            if (!errors[i].empty()) MOIRE_ICE("LLVM could not compile a chunk: {}", errors[i]);
            if (store && compiled[i]) store->store(keys[i], objects[i]->getBuffer());
            if (auto err = jit->addObjectFile(std::move(objects[i])))
                MOIRE_ICE("LLVM JIT rejected a chunk: {}", errorText(std::move(err)));
        }
    }

    // An object from the store, if it is there and is an object file for this target.
    static std::unique_ptr<llvm::MemoryBuffer> loadObject(ObjectStore& store,
                                                          const std::string& key) {
        std::optional<std::string> bytes = store.load(key);
        if (!bytes) return nullptr;
        auto buffer = llvm::MemoryBuffer::getMemBufferCopy(*bytes, key);
        auto parsed = llvm::object::ObjectFile::createObjectFile(buffer->getMemBufferRef());
        if (!parsed) {
            llvm::consumeError(parsed.takeError());
            return nullptr;
        }
        return buffer;
    }

    std::atomic<int> hits{0};
    std::atomic<int64_t> optimiseNs{0}, codegenNs{0};
    uint64_t codeConfig = 0;
};

LlvmJitBackend::LlvmJitBackend(size_t chunkInsts)
    : LlvmJitBackend([chunkInsts] {
          Options o;
          o.chunkInsts = chunkInsts;
          return o;
      }()) {}
LlvmJitBackend::LlvmJitBackend(const Options& options) : impl_(std::make_unique<Impl>(options)) {}
LlvmJitBackend::~LlvmJitBackend() = default;

int LlvmJitBackend::compileCount() const {
    return impl_->compiled;
}

int LlvmJitBackend::storeHits() const {
    return impl_->hits;
}

LlvmJitBackend::Seconds LlvmJitBackend::llvmSeconds() const {
    return {impl_->optimiseNs * 1e-9, impl_->codegenNs * 1e-9};
}

bool LlvmJitBackend::callsLibm(ir::Op op) {
    return llvmbackend::callsLibm(op);
}

unsigned LlvmJitBackend::lanes() const {
    return impl_->lanes;
}

std::unique_ptr<CompiledKernel> LlvmJitBackend::compile(const ir::Function& kernel) {
    uint64_t hash = ir::structuralHash(kernel);
    std::lock_guard<std::mutex> lock(impl_->mutex);
    auto it = impl_->cache.find(hash);
    if (it == impl_->cache.end()) {
        std::string name = fmt::format("moire_kernel_{:016x}", hash);
        auto modules = impl_->translate(kernel, name);
        impl_->compileModules(modules);
        auto sym = impl_->jit->lookup(name);
        if (!sym) MOIRE_ICE("LLVM JIT lookup: {}", errorText(sym.takeError()));
        it = impl_->cache.emplace(hash, sym->toPtr<llvmbackend::TileFn>()).first;
        ++impl_->compiled;
    }
    return std::make_unique<JitKernel>(it->second, kernel.numOutputs);
}

std::string LlvmJitBackend::dumpLlvm(const ir::Function& kernel) {
    std::lock_guard<std::mutex> lock(impl_->mutex);
    std::string s;
    llvm::raw_string_ostream os(s);
    for (auto& m : impl_->translate(kernel, "moire_kernel")) {
        impl_->prepare(*m.module, *impl_->tm);
        m.module->print(os, nullptr);
    }
    return os.str();
}

} // namespace moire
