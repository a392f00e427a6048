#include "compiler/backend/llvm/LlvmJit.h"

#include "compiler/backend/llvm/LlvmTranslate.h"
#include "compiler/diag/Diagnostics.h"

#include <algorithm>
#include <atomic>
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

// glibc's vector maths library (libmvec): 8-lane (AVX2) and 4-lane (SSE) versions of the
// libm functions kernels call, so the loop vectoriser can run pixels in SIMD lanes even when
// the kernel calls sinf or atan2f. Accuracy: within 4 ulp, like the scalar functions.
constexpr const char* kLibmvec[][3] = {
    // scalar, 4 lanes, 8 lanes
    {"sinf", "_ZGVbN4v_sinf", "_ZGVdN8v_sinf"},
    {"cosf", "_ZGVbN4v_cosf", "_ZGVdN8v_cosf"},
    {"tanf", "_ZGVbN4v_tanf", "_ZGVdN8v_tanf"},
    {"asinf", "_ZGVbN4v_asinf", "_ZGVdN8v_asinf"},
    {"acosf", "_ZGVbN4v_acosf", "_ZGVdN8v_acosf"},
    {"atanf", "_ZGVbN4v_atanf", "_ZGVdN8v_atanf"},
    {"atan2f", "_ZGVbN4vv_atan2f", "_ZGVdN8vv_atan2f"},
    {"expf", "_ZGVbN4v_expf", "_ZGVdN8v_expf"},
    {"logf", "_ZGVbN4v_logf", "_ZGVdN8v_logf"},
    {"powf", "_ZGVbN4vv_powf", "_ZGVdN8vv_powf"},
};

// Loads libmvec into the process once; false where it is missing (kernels stay scalar).
bool libmvecAvailable() {
    static const bool loaded = [] {
        std::string err;
        if (llvm::sys::DynamicLibrary::LoadLibraryPermanently("libmvec.so.1", &err)) return false;
        for (const auto& f : kLibmvec)
            if (!llvm::sys::DynamicLibrary::SearchForAddressOfSymbol(f[1]) ||
                !llvm::sys::DynamicLibrary::SearchForAddressOfSymbol(f[2]))
                return false;
        return true;
    }();
    return loaded;
}

// The standard -O2 pipeline, for the host CPU.
void optimise(llvm::Module& m, llvm::TargetMachine& tm) {
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
    llvm::ModulePassManager mpm = pb.buildPerModuleDefaultPipeline(llvm::OptimizationLevel::O2);
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
    std::unique_ptr<llvm::TargetMachine> tm;
    std::mutex mutex;
    std::unordered_map<uint64_t, llvmbackend::TileFn> cache;
    int compiled = 0;
    Options options;
    unsigned chunkVectorWidth = 0;

    explicit Impl(const Options& o) : options(o) {
        initialiseLlvmOnce();
        auto detected = llvm::orc::JITTargetMachineBuilder::detectHost();
        if (!detected)
            MOIRE_ICE("LLVM cannot target this host: {}", errorText(detected.takeError()));
        jtmb = std::move(*detected);
        jtmb->setCodeGenOptLevel(llvm::CodeGenOpt::Default);
        tm = targetMachine();
        chunkVectorWidth = options.chunkVectorWidth == Options::kWidestFloatVector
                               ? widestFloatVector(*tm)
                               : static_cast<unsigned>(std::max(0, options.chunkVectorWidth));
        codeConfig =
            fnv1a(fmt::format("{}|{}|{}|{}|{}|{}", LLVM_VERSION_STRING, tm->getTargetCPU().str(),
                              tm->getTargetFeatureString().str(), options.chunkInsts,
                              chunkVectorWidth, options.classicChunks));
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
        return llvmbackend::translate(kernel, name, t);
    }

    void prepare(llvm::Module& m, llvm::TargetMachine& machine) {
        m.setDataLayout(jit->getDataLayout());
        m.setTargetTriple(machine.getTargetTriple().str());
        optimise(m, machine);
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
        std::atomic<size_t> next{0};
        auto work = [&](llvm::TargetMachine& machine) {
            llvm::orc::SimpleCompiler compile(machine);
            for (size_t i; (i = next++) < modules.size();) {
                if (store) {
                    if (auto object = loadObject(*store, keys[i])) {
                        objects[i] = std::move(object);
                        ++hits;
                        continue;
                    }
                }
                prepare(*modules[i].module, machine);
                auto object = compile(*modules[i].module);
                if (object) {
                    objects[i] = std::move(*object);
                    compiled[i] = 1;
                } else {
                    errors[i] = errorText(object.takeError());
                }
            }
        };
        // Target machines are made here: MOIRE_ICE must not throw on a worker thread.
        std::vector<std::unique_ptr<llvm::TargetMachine>> machines;
        for (unsigned t = 0; t < threads; ++t) machines.push_back(targetMachine());
        std::vector<std::thread> workers;
        for (unsigned t = 1; t < threads; ++t) workers.emplace_back(work, std::ref(*machines[t]));
        work(*machines[0]);
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
